// SPDX-License-Identifier: GPL-3.0-or-later
// api/internal.hpp -- what the library's public types hold, and the crossing of its boundary:
// exact numbers (mpq_class <-> Rational) and exceptions (the internal types -> impactcert::api's).
#pragma once

#include <impactcert/impactcert.hpp>

#include "base/errors.hpp"
#include "model/law.hpp"
#include "model/system.hpp"

#include <memory>
#include <string>
#include <utility>

namespace impactcert::api {

struct System::Impl {
    impactcert::System system;
};

struct Law::Impl {
    impactcert::Model model;
};

namespace detail {

impactcert::Rational to_internal(const mpq_class& x);
mpq_class to_public(const impactcert::Rational& x);
impactcert::Vector to_internal(const Vector& v, const std::string& where);
Vector to_public(const impactcert::Vector& v);

// Runs f, turning the core's exceptions into the API's: bad input (InputError, a JSON document
// that cannot be read) -> api::InputError; a limit (DeriveLimit, LimitExceeded, ...) ->
// api::LimitError. Bugs (std::logic_error) and std::bad_alloc pass unchanged.
void rethrow_as_api();
template <class F>
auto translated(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const Error&) {
        throw;
    } catch (...) {
        rethrow_as_api();
        throw; // not reached
    }
}

} // namespace detail
} // namespace impactcert::api
