// SPDX-License-Identifier: GPL-3.0-or-later
// Uses the installed library (impactcert::impactcert) as a downstream project would: derives the
// 3-ball chain's sequential law, verifies it, certifies it and checks the certificate, evaluates
// it exactly, and fuzzes a float implementation of it in-process. Exit 0 when every result is
// the expected one, else 1 with the reason.
#include <impactcert/impactcert.hpp>

#include <cmath>
#include <iostream>

namespace ic = impactcert::api;

int fail(const std::string& why) {
    std::cerr << "library consumer: " << why << "\n";
    return 1;
}

int main() {
    const ic::System chain = ic::System::chain({1, 1, 1});
    const ic::Derivation d = ic::derive(chain); // elastic: the paper's law, every claim proved
    if (!d.law)
        return fail("no law derived");
    const ic::Report report = ic::verify(*d.law);
    if (report.verdict != "proved")
        return fail("verdict " + report.verdict);
    if (ic::check_certificate(ic::certify(*d.law)).exit_status != 0)
        return fail("the certificate is not verified");
    // gamma- = (-1, 0): ball 1 hits balls 2 and 3 at rest; ball 3 leaves: gamma+ = (0, 1).
    const auto values = d.law->evaluate({-1, 0});
    if (values.size() != 1 || values[0] != ic::Vector{0, 1})
        return fail("evaluate");
    // A float implementation that swaps the outputs: violations expected.
    ic::FuzzOptions fo;
    fo.samples = 2000;
    fo.max_rel_error = 1e-9;
    const ic::FuzzResult bad = ic::fuzz(
        *d.law,
        [&](const double* in, double* out, std::size_t count) {
            for (std::size_t i = 0; i < count; ++i) {
                out[2 * i] = in[2 * i + 1];
                out[2 * i + 1] = in[2 * i];
            }
        },
        fo);
    if (bad.exit_status != 1 || bad.violating == 0)
        return fail("the swapping implementation passed the fuzzer");
    try {
        (void)ic::Law::parse("{}");
        return fail("an empty document was accepted");
    } catch (const ic::InputError& e) {
        if (e.exit_status() != 2)
            return fail("exit status of bad input");
    }
    std::cout << "impactcert " << ic::version() << ": " << d.law->name() << ", " << d.law->pieces() << " pieces, "
              << report.verdict << "; fuzz: " << bad.verdict << "\n";
    return 0;
}
