// SPDX-License-Identifier: GPL-3.0-or-later
// SHA-256 (FIPS 180-4). The round constants are computed, not typed: K[i] and the initial hash
// are the first 32 fractional bits of the cube and square roots of the first primes, obtained
// exactly with integer roots.
#include "sha256.hpp"

#include <gmpxx.h>

#include <cstdint>
#include <sstream>
#include <vector>

namespace impactcert_check::detail {

std::string sha256_hex(const std::string& message) {
    static const std::vector<std::uint32_t> primes = [] {
        std::vector<std::uint32_t> p;
        for (std::uint32_t n = 2; p.size() < 64; ++n) {
            bool prime = true;
            for (auto d : p)
                prime = prime && n % d != 0;
            if (prime)
                p.push_back(n);
        }
        return p;
    }();
    auto frac_bits = [](std::uint32_t p, unsigned root) {
        mpz_class x = mpz_class(p) << (32 * root), r;
        mpz_root(r.get_mpz_t(), x.get_mpz_t(), root);
        mpz_class low = r & mpz_class(0xffffffffUL);
        return static_cast<std::uint32_t>(low.get_ui());
    };
    std::uint32_t k[64], h[8];
    for (int i = 0; i < 64; ++i)
        k[i] = frac_bits(primes[static_cast<std::size_t>(i)], 3);
    for (int i = 0; i < 8; ++i)
        h[i] = frac_bits(primes[static_cast<std::size_t>(i)], 2);
    auto rotr = [](std::uint32_t x, int n) { return (x >> n) | (x << (32 - n)); };

    std::string m = message;
    const std::uint64_t bits = static_cast<std::uint64_t>(message.size()) * 8;
    m += static_cast<char>(0x80);
    while (m.size() % 64 != 56)
        m += '\0';
    for (int i = 7; i >= 0; --i)
        m += static_cast<char>((bits >> (8 * i)) & 0xff);
    for (std::size_t chunk = 0; chunk < m.size(); chunk += 64) {
        std::uint32_t w[64];
        for (int t = 0; t < 16; ++t) {
            w[t] = 0;
            for (int b = 0; b < 4; ++b)
                w[t] = (w[t] << 8) | static_cast<unsigned char>(m[chunk + static_cast<std::size_t>(4 * t + b)]);
        }
        for (int t = 16; t < 64; ++t) {
            const std::uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
            const std::uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
            w[t] = w[t - 16] + s0 + w[t - 7] + s1;
        }
        std::uint32_t a = h[0], b = h[1], c = h[2], d = h[3], e = h[4], f = h[5], g = h[6], hh = h[7];
        for (int t = 0; t < 64; ++t) {
            const std::uint32_t t1 = hh + (rotr(e, 6) ^ rotr(e, 11) ^ rotr(e, 25)) + ((e & f) ^ (~e & g)) + k[t] + w[t];
            const std::uint32_t t2 = (rotr(a, 2) ^ rotr(a, 13) ^ rotr(a, 22)) + ((a & b) ^ (a & c) ^ (b & c));
            hh = g;
            g = f;
            f = e;
            e = d + t1;
            d = c;
            c = b;
            b = a;
            a = t1 + t2;
        }
        h[0] += a; h[1] += b; h[2] += c; h[3] += d; h[4] += e; h[5] += f; h[6] += g; h[7] += hh;
    }
    std::ostringstream out;
    for (auto word : h)
        for (int shift = 28; shift >= 0; shift -= 4)
            out << "0123456789abcdef"[(word >> shift) & 15];
    return out.str();
}

} // namespace impactcert_check::detail
