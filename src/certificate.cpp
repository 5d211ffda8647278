#include "certificate.hpp"

#include "json.hpp"
#include "law_json.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <stdexcept>

namespace impactcert {

const char* statement_of(const std::string& id) {
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

Json make_certificate(const Model& model, VerifyReport&& report) {
    const Json law = law_to_json(model.law());
    Json cert;
    cert["format"] = kCertificateFormat;
    cert["tool"] = std::string("impactcert ") + IMPACTCERT_VERSION;
    cert["law_sha256"] = sha256_hex(law.dump());
    cert["law"] = law;
    cert["verdict"] = report.verdict();
    cert["system"] = Json{{"G", to_json(model.G())}, {"H", to_json(model.H())}};
    Json obligations = Json::array();
    for (auto& o : report.obligations) {
        Json item;
        item["id"] = o.id;
        item["statement"] = statement_of(o.id);
        item["method"] = o.method;
        item["claimed"] = o.claimed;
        item["verdict"] = to_string(o.verdict);
        item["checks"] = o.checks;
        item["data"] = o.data.is_null() ? Json::object() : std::move(o.data);
        if (o.verdict == Verdict::refuted)
            item["counterexample"] = o.counterexample;
        if (o.verdict == Verdict::undecided)
            item["limit"] = o.limit;
        obligations.push_back(std::move(item));
    }
    cert["obligations"] = obligations;
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

void write_certificate(std::ostream& out, const Json& certificate) {
    // Each line is printed as certificate_text prints it; the stream takes the text as it comes.
    struct Sink {
        std::ostream& os;
        Sink& operator+=(const std::string& s) {
            os << s;
            return *this;
        }
        Sink& operator+=(const char* s) {
            os << s;
            return *this;
        }
        Sink& operator+=(char ch) {
            os << ch;
            return *this;
        }
    } sink{out};
    print(certificate, 0, sink);
    out << "\n";
}

} // namespace impactcert
