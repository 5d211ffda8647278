// SPDX-License-Identifier: GPL-3.0-or-later
// sha256.hpp -- SHA-256 (FIPS 180-4), the checker's own: the law's hash in a certificate is
// recomputed without the prover's OpenSSL.
#pragma once

#include <string>

namespace impactcert_check::detail {

// The lowercase hex digest of `message`.
std::string sha256_hex(const std::string& message);

} // namespace impactcert_check::detail
