// SPDX-License-Identifier: GPL-3.0-or-later
// certificate.hpp -- the `impactcert-certificate/1` document (SPEC section 4, schema in
// proofs/README.md).
//
// Contract: make_certificate(model, report) is deterministic: the same law gives the same bytes
// (fixed key order, no times, rationals in lowest terms). It holds the law in canonical form,
// the SHA-256 of that form's compact text, the tool version, G and H, and for every obligation
// its statement, method, claim, verdict, the evidence it was decided on (`data`) and, when
// refuted, the counterexample. impactcert-check (src/checker/) re-establishes all of it from
// the law alone, sharing no code with this file.
#pragma once

#include "prover/obligations.hpp"

#include <ostream>
#include <string>

namespace impactcert {

inline constexpr const char* kCertificateFormat = "impactcert-certificate/1";

Json make_certificate(const Model& model, const VerifyReport& report);
// The same, moving the evidence out of `report` (a large law's evidence is not held twice).
Json make_certificate(const Model& model, VerifyReport&& report);
// One shard's part (shard.hpp): the head without the top verdict, "shard": {index, count}, and
// the obligations the shard owns, with nonexpansive's slice of pair blocks in every part.
struct Shard;
Json make_certificate_part(const Model& model, VerifyReport&& report, const Shard& shard);
std::string certificate_text(const Json& certificate); // what `certify -o` writes
void write_certificate(std::ostream& out, const Json& certificate); // the same bytes, streamed

// The same bytes again, one obligation at a time (`certify`): the header needs the top verdict,
// so it comes from a first verification without evidence; each obligation is then written as
// verify_streaming decides it, and finish() requires the two verdicts to agree.
class CertificateWriter {
  public:
    CertificateWriter(std::ostream& out, const Model& model, const std::string& verdict);
    void add(ObligationResult& o); // moves o.data out
    // After the obligations: the certificate's "worst_case" (worst_case.hpp), checked by
    // impactcert-check when present.
    void add_worst_case(const Json& worst_case);
    void finish();

  private:
    std::ostream& out_;
    bool first_ = true;
    bool closed_ = false; // the obligations' array is closed (a worst case follows it)
};
std::string sha256_hex(const std::string& bytes);
const char* statement_of(const std::string& obligation_id, bool friction = false);

} // namespace impactcert
