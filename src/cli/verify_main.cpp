// SPDX-License-Identifier: GPL-3.0-or-later
// verify_main.cpp -- the program impactcert-verify: `impactcert verify` alone, with the same
// options, output and exit statuses (cli/options.hpp). It compiles the exact core and verify's
// command line only: the first build of a fresh machine (scripts/verify) and a CI gate that
// never derives, sweeps or fuzzes take about half the time of the full impactcert program.
// (cli/options.hpp is not included: CLI11's headers stay in cli/options.cpp's unit.)
namespace impactcert::cli {
int verify_program(int argc, char** argv); // cli/options.hpp
}

int main(int argc, char** argv) { return impactcert::cli::verify_program(argc, argv); }
