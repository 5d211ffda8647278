// SPDX-License-Identifier: GPL-3.0-or-later
#include "prover/certificate.hpp"
#include "prover/shard.hpp"

#include "base/json.hpp"
#include "model/law_json.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <stdexcept>

namespace impactcert {

const char* statement_of(const std::string& id, bool friction) {
    if (friction && id == "kinematic") return "gamma_N+ >= 0 for every gamma- (the normals; tangential velocities have no sign)";
    if (friction && id == "kinetic")
        return "Lambda = H (Q_i - I) gamma in the friction cone on C_i: Lambda_N >= 0, |Lambda_T| <= mu Lambda_N (per "
               "tangent; a . Lambda_T <= mu Lambda_N for every facet a of a friction polygon)";
    if (id == "coulomb")
        return "on C_i, Lambda in the friction cone and friction opposes the slip: xi_T = gamma_T+ + e_T gamma_T- > 0 "
               "implies Lambda_T = -mu Lambda_N, xi_T < 0 implies Lambda_T = +mu Lambda_N (per tangent; at a contact "
               "with a friction polygon P, Lambda_T minimises Lambda_T . xi_T over mu Lambda_N P)";
    if (id == "fan") return "the cones cover R^c and overlap only on shared faces";
    if (id == "P1") return "Q_i v = Q_j v on every ray v shared by C_i and C_j";
    if (id == "P2") return "|Q_i x|_H = |x|_H for all x and every piece";
    if (id == "P3") return "Q_i maps C_i onto the closed positive orthant";
    if (id == "kinematic") return "gamma+ >= 0 for every gamma-";
    if (id == "kinetic") return "Lambda = H (Q_i - I) gamma >= 0 on C_i";
    if (id == "energetic") return "|Q_i x|_H <= |x|_H on C_i";
    if (id == "identities") return "the declared factorisations hold";
    if (id == "single-impacts") return "each declared piece equals Q^(k)(e) = I - (1+e) G e_k e_k^T / G_kk";
    if (id == "nonexpansive") return "|S(a) - S(b)|_H <= |a - b|_H for all a, b (pairwise copositivity)";
    if (id == "nonexpansive-lemma") return "|S(a) - S(b)|_H <= |a - b|_H for all a, b (fan + P1 + per-piece PSD)";
    if (id == "outcomes") return "each declared experiment u- maps to the declared u+";
    if (id == "symmetries")
        return "each declared (P, P'): H-isometries, P C_i = C_sigma(i) and Q_sigma(i) P = P' Q_i, so S(P x) = P' S(x)";
    throw std::logic_error("no statement for " + id);
}

std::string sha256_hex(const std::string& bytes) {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1)
        throw std::runtime_error("SHA-256 failed");
    static const char* hex = "0123456789abcdef";
    std::string out;
    for (unsigned int i = 0; i < length; ++i) {
        out += hex[digest[i] >> 4];
        out += hex[digest[i] & 15];
    }
    return out;
}

Json make_certificate(const Model& model, const VerifyReport& report) {
    VerifyReport copy = report;
    return make_certificate(model, std::move(copy));
}

namespace {

Json certificate_head(const Model& model, const std::string& verdict) {
    const Json law = law_to_json(model.law());
    Json cert;
    cert["format"] = kCertificateFormat;
    cert["tool"] = std::string("impactcert ") + IMPACTCERT_VERSION;
    cert["law_sha256"] = sha256_hex(law.dump());
    cert["law"] = law;
    cert["verdict"] = verdict;
    cert["system"] = Json{{"G", to_json(model.G())}, {"H", to_json(model.H())}};
    return cert;
}

Json obligation_item(const ObligationResult& o, Json data) {
    Json item;
    item["id"] = o.id;
    item["statement"] = statement_of(o.id, o.friction);
    item["method"] = o.method;
    item["claimed"] = o.claimed;
    item["verdict"] = to_string(o.verdict);
    item["checks"] = o.checks;
    item["data"] = data.is_null() ? Json::object() : std::move(data);
    if (o.verdict == Verdict::refuted)
        item["counterexample"] = o.counterexample;
    if (o.verdict == Verdict::undecided)
        item["limit"] = o.limit;
    return item;
}

} // namespace

Json make_certificate_part(const Model& model, VerifyReport&& report, const Shard& shard) {
    Json part = certificate_head(model, "");
    part.erase("verdict"); // a slice has no top verdict: the merged certificate has
    part["format"] = kCertificatePartFormat;
    part["shard"] = Json{{"index", shard.index + 1}, {"count", shard.count}};
    Json obligations = Json::array();
    for (std::size_t i = 0; i < report.obligations.size(); ++i) {
        auto& o = report.obligations[i];
        const bool slice = o.data.is_object() && o.data.contains("slice");
        if (slice || (owns(shard, i) && o.method != "not requested"))
            obligations.push_back(obligation_item(o, std::move(o.data)));
    }
    part["obligations"] = std::move(obligations);
    return part;
}

Json make_certificate(const Model& model, VerifyReport&& report) {
    Json cert = certificate_head(model, report.verdict());
    Json obligations = Json::array();
    for (auto& o : report.obligations)
        obligations.push_back(obligation_item(o, std::move(o.data)));
    cert["obligations"] = std::move(obligations);
    return cert;
}

namespace {

bool is_flat(const Json& j) {
    // Scalars, vectors of scalars and matrices of scalars print on one line.
    if (!j.is_structured())
        return true;
    if (j.is_object())
        return j.empty();
    for (const auto& x : j)
        if (x.is_object() || (x.is_array() && std::any_of(x.begin(), x.end(), [](const Json& y) {
                                  return y.is_structured();
                              })))
            return false;
    return true;
}

template <class Out> void print(const Json& j, int depth, Out& out) {
    if (is_flat(j)) {
        out += j.dump();
        return;
    }
    const std::string pad(static_cast<std::size_t>(2 * (depth + 1)), ' ');
    const bool object = j.is_object();
    out += object ? "{\n" : "[\n";
    bool first = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
        out += first ? "" : ",\n";
        first = false;
        out += pad;
        if (object)
            out += Json(it.key()).dump() + ": ";
        print(*it, depth + 1, out);
    }
    out += "\n" + std::string(static_cast<std::size_t>(2 * depth), ' ') + (object ? "}" : "]");
}

} // namespace

std::string certificate_text(const Json& certificate) {
    std::string out;
    print(certificate, 0, out);
    return out + "\n";
}

namespace {

// certificate_text's printer writing to a stream as it goes.
struct StreamSink {
    std::ostream& os;
    StreamSink& operator+=(const std::string& s) {
        os << s;
        return *this;
    }
    StreamSink& operator+=(const char* s) {
        os << s;
        return *this;
    }
    StreamSink& operator+=(char ch) {
        os << ch;
        return *this;
    }
};

} // namespace

void write_certificate(std::ostream& out, const Json& certificate) {
    StreamSink sink{out};
    print(certificate, 0, sink);
    out << "\n";
}

// The layout of print() for the top object: keys at depth 1, the obligations' items at depth 2.
CertificateWriter::CertificateWriter(std::ostream& out, const Model& model, const std::string& verdict) : out_(out) {
    const Json head = certificate_head(model, verdict);
    StreamSink sink{out_};
    out_ << "{\n";
    for (auto it = head.begin(); it != head.end(); ++it) {
        out_ << "  " << Json(it.key()).dump() << ": ";
        print(*it, 1, sink);
        out_ << ",\n";
    }
    out_ << "  \"obligations\": [\n";
}

void CertificateWriter::add(ObligationResult& o) {
    StreamSink sink{out_};
    out_ << (first_ ? "" : ",\n") << "    ";
    first_ = false;
    print(obligation_item(o, std::move(o.data)), 2, sink);
}

void CertificateWriter::add_worst_case(const Json& worst_case) {
    StreamSink sink{out_};
    out_ << "\n  ],\n  \"worst_case\": ";
    print(worst_case, 1, sink);
    closed_ = true;
}

void CertificateWriter::finish() { out_ << (closed_ ? "\n}\n" : "\n  ]\n}\n"); }

} // namespace impactcert
