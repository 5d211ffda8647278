// SPDX-License-Identifier: GPL-3.0-or-later
#include "exact/matrix.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

using namespace impactcert;
using impactcert::test::q;
using impactcert::test::vec;

TEST_CASE("rationals: the law-file grammar reads integers, fractions and exact decimals", "[rational]") {
    CHECK(to_string(q("3")) == "3");
    CHECK(to_string(q("-7/12")) == "-7/12");
    CHECK(to_string(q("+14/24")) == "7/12");
    CHECK(to_string(q("0.25")) == "1/4");
    CHECK(to_string(q("-0.1")) == "-1/10");      // exactly one tenth, not the double
    CHECK(to_string(q("000.500")) == "1/2");
    CHECK(to_string(q("6/3")) == "2");
    CHECK(to_string(q("-0")) == "0");
}

TEST_CASE("rationals: malformed text and zero denominators are rejected with a reason", "[rational]") {
    for (const char* bad : {"", "-", "1/", "/2", "1.", ".5", "1e3", "1.0e3", "0x10", "1/2/3", "1 /2",
                            "1/-2", "one", "1.2.3", "--1", "inf", "nan"}) {
        std::string why;
        INFO("input: '" << bad << "'");
        CHECK_FALSE(parse_rational(bad, &why));
        CHECK_FALSE(why.empty());
    }
    std::string why;
    CHECK_FALSE(parse_rational("3/0", &why));
    CHECK(why == "zero denominator");
    CHECK_FALSE(parse_rational("-3/000", &why));
}

TEST_CASE("rationals: hundreds of digits survive parsing and arithmetic exactly", "[rational]") {
    const std::string big(300, '7');
    const Rational x = q(big + "/" + big + "1");
    const Rational y = q("1/" + big);
    CHECK(to_string(x * (q(big + "1") / q(big))) == "1");
    CHECK(to_string(y * q(big)) == "1");
    CHECK(to_string(q("0." + std::string(200, '0') + "1")) == "1/1" + std::string(201, '0'));
}

TEST_CASE("rationals: command-line numbers add exact hex floats", "[rational]") {
    CHECK(to_string(*parse_cli_number("0x1.8p-3")) == "3/16");
    CHECK(to_string(*parse_cli_number("-0x1p+2")) == "-4");
    CHECK(to_string(*parse_cli_number("0x.8")) == "1/2");
    CHECK(to_string(*parse_cli_number("0x1.fffffffffffffp+1023")) ==
          to_string(q("179769313486231570814527423731704356798070567525844996598917476803157260780028538760589558632766878171540458953514382464234321326889464182768467546703537516986049910576551282076245490090389328944075868508455133942304583236903222948165808559332123348274797826204144723168738177180919299881250404026184124858368")));
    CHECK(to_string(*parse_cli_number("0x1p-1074")) == "1/" + to_string(q("202402253307310618352495346718917307049556649764142118356901358027430339567995346891960383701437124495187077864316811911389808737385793476867013399940738509921517424276566361364466907742093216341239767678472745068562007483424692698618103355649159556340810056512358769552333414615230502532186327508646006263307707741093494784")));
    CHECK(to_string(*parse_cli_number("1/3")) == "1/3");
    for (const char* bad : {"0x", "0xg", "0x1p", "0x1.8q", "0x1p+x"})
        CHECK_FALSE(parse_cli_number(bad));
}

TEST_CASE("rationals: command-line decimals take an exact decimal exponent - law files do not", "[rational]") {
    CHECK(to_string(*parse_cli_number("1e300")) == "1" + std::string(300, '0'));
    CHECK(to_string(*parse_cli_number("2.5e-3")) == "1/400");
    CHECK(to_string(*parse_cli_number("-1E+2")) == "-100");
    CHECK(to_string(*parse_cli_number("+0.125e1")) == "5/4");
    CHECK(to_string(*parse_cli_number("7e0")) == "7");
    CHECK(to_string(*parse_cli_number("1e-0000000000000000000003")) == "1/1000"); // leading zeros
    CHECK(to_string(*parse_cli_number("1e-400")) == "1/1" + std::string(400, '0'));
    CHECK(to_string(*parse_cli_number("0e99999")) == "0");
    CHECK(parse_cli_number("1e100000"));
    for (const char* bad : {"1e", "1e+", "e3", "1e3.5", "1.e3", ".5e3", "1/2e3", "1e3/2", "1ee3", "1e 3", "1e0x3",
                            "0x1e3p1x"}) {
        std::string why;
        INFO("input: '" << bad << "'");
        CHECK_FALSE(parse_cli_number(bad, &why));
        CHECK_FALSE(why.empty());
    }
    // Absurd exponents are refused at once, with the limit in the reason.
    for (const char* absurd : {"1e999999999", "1e-999999999", "1e100001", "5e99999999999999999999999999"}) {
        std::string why;
        INFO("input: '" << absurd << "'");
        CHECK_FALSE(parse_cli_number(absurd, &why));
        CHECK(why.find("100000") != std::string::npos);
    }
    std::string why;
    CHECK_FALSE(parse_rational("1e300", &why)); // SPEC section 4: no exponent in law files
    CHECK_FALSE(why.empty());
}

TEST_CASE("rationals: signs are three-way", "[rational]") {
    CHECK(sign_of(q("-1/1000000000000000000000")) == Sign::negative);
    CHECK(sign_of(q("0")) == Sign::zero);
    CHECK(sign_of(q("1/1000000000000000000000")) == Sign::positive);
}

TEST_CASE("matrices: inverse, determinant and solve are exact", "[matrix]") {
    const Matrix G = Matrix::from_rows({vec({"2", "-1"}), vec({"-1", "2"})});
    const Matrix H = *inverse(G);
    CHECK(H == Matrix::from_rows({vec({"2/3", "1/3"}), vec({"1/3", "2/3"})}));
    CHECK(G * H == Matrix::identity(2));
    CHECK(to_string(determinant(G)) == "3");
    CHECK_FALSE(inverse(Matrix::from_rows({vec({"1", "2"}), vec({"1/2", "1"})})));
    CHECK(to_string(determinant(Matrix::from_rows({vec({"0", "1"}), vec({"1", "0"})}))) == "-1");
    CHECK(*solve(G, vec({"1", "1"})) == vec({"1", "1"}));
}

TEST_CASE("matrices: a ray's primitive representative identifies its direction", "[matrix]") {
    CHECK(primitive_ray(vec({"0", "5"})) == vec({"0", "1"}));
    CHECK(primitive_ray(vec({"-1/2", "1/3"})) == vec({"-3", "2"}));
    CHECK(primitive_ray(vec({"-6", "4"})) == vec({"-3", "2"}));
    CHECK(primitive_ray(vec({"-6", "4"})) != primitive_ray(vec({"6", "-4"})));
    CHECK(primitive_ray(vec({"10000000000000000000000000000000", "0", "0"})) == vec({"1", "0", "0"}));
}

TEST_CASE("rationals: readable decimal text, exact where it can be and marked ~ where rounded", "[rational]") {
    auto r = [](const char* t) { return *parse_cli_number(t); };
    CHECK(readable_text(r("0")) == "0");
    CHECK(readable_text(r("3/4")) == "0.75");
    CHECK(readable_text(r("-7")) == "-7");
    CHECK(readable_text(r("959/4")) == "239.75");
    CHECK(readable_text(r("1/3")) == "~0.33333333333333333");
    CHECK(readable_text(r("-2/3")) == "~-0.66666666666666667");
    CHECK(readable_text(r("2290675898897905/8796093022208")) == "~260.41969919082305");
    CHECK(readable_text(r("1/100000")) == "0.00001");
    CHECK(readable_text(r("1/1000000")) == "1e-6");
    CHECK(readable_text(r("123456789012345678")) == "~1.2345678901234568e+17");
    CHECK(readable_text(r("12345678901234567")) == "12345678901234567");
    CHECK(readable_text(r("99999999999999999999/1000")) == "~1e+17"); // rounded up past a power of ten
    CHECK(readable_text(r("1e100000")) == "1e+100000");
    CHECK(readable_text(r("-3e-100000")) == "-3e-100000");
    CHECK(readable_text(r("1/3"), 3) == "~0.333");
    CHECK(readable_text(r("2/3"), 1) == "~0.7");
    CHECK(readable_text(r("5/2"), 1) == "~3"); // ties away from zero
}
