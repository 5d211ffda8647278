// SPDX-License-Identifier: GPL-3.0-or-later
// derived_law.cpp -- the claims and the text of a derived law (derived_law.hpp).
#include "derive/derived_law.hpp"

#include "base/json.hpp"
#include "model/law_json.hpp"

namespace impactcert {

// The canonical law, with the derivation's description after the name.
std::string law_file_text(const Law& law) {
    const Json canonical = law_to_json(law);
    Json out;
    for (auto it = canonical.begin(); it != canonical.end(); ++it) {
        out[it.key()] = it.value();
        if (it.key() == "name" && !law.description.empty())
            out["description"] = law.description;
    }
    return out.dump(2) + "\n";
}

// What a derived law claims (docs/laws.md, "What a law claims"): what a physical impact law is
// expected to satisfy -- a function (fan), continuous (P1), no penetration (kinematic), pushing
// impulses (kinetic; with friction inside the cone, and coulomb), no energy gain (energetic) --
// and whatever is declared (identities, single impacts, outcomes, symmetries). Energy
// conservation (P2) only for an elastic frictionless law (every restitution 1); non-expansivity
// in H (nonexpansive, nonexpansive-lemma) for frictionless laws; P3 (each cone onto the orthant,
// the paper's construction) never by default. --claims on verify, certify and report overrides.
void set_expected_claims(Law& law, const std::vector<Rational>& restitution) {
    const bool friction = !law.friction.empty();
    bool elastic = !friction;
    for (const auto& e : restitution)
        elastic = elastic && e == Rational(1);
    std::vector<std::string> claims;
    for (const char* id : obligation_ids(friction)) {
        const std::string s = id;
        if (!law_applies(law, s) || s == "P3" || (s == "P2" && !elastic) ||
            (friction && (s == "nonexpansive" || s == "nonexpansive-lemma")))
            continue;
        claims.push_back(s);
    }
    law.claims = claims;
}

Json not_a_function_json(const Vector& gamma_minus, const std::string& reason) {
    Json j;
    j["format"] = "impactcert-derive/1";
    j["verdict"] = "not-a-function";
    j["gamma_minus"] = to_json(gamma_minus);
    j["reason"] = reason;
    return j;
}

std::string not_a_function_text(const Vector& gamma_minus, const std::string& reason) {
    return "the sequential law with friction is not a function: at gamma- = " + short_text(gamma_minus) + " " + reason;
}

std::string not_a_function_text(const NotAFunction& w) {
    const std::string head = std::string(w.frictionless ? "the Newton law" : "the Newton law with friction") +
                             " is not a function: gamma- = " + short_text(w.gamma_minus) +
                             (w.u_minus.empty() ? std::string() : " (u- = " + short_text(w.u_minus) + ")");
    if (w.none)
        return head + " has no solution";
    if (!w.u_a.empty())
        return head + " has two solutions, u+ = " + short_text(w.u_a) + " (mode " + w.mode_a + ") and " +
               short_text(w.u_b) + " (mode " + w.mode_b + ")";
    return head + " has two solutions, gamma+ = " + short_text(w.gamma_a) + " (mode " + w.mode_a + ") and " +
           short_text(w.gamma_b) + " (mode " + w.mode_b + ")";
}

Json not_a_function_json(const NotAFunction& w) {
    Json j;
    j["format"] = "impactcert-derive/1";
    j["verdict"] = w.none ? "no-solution" : "two-solutions";
    j["gamma_minus"] = to_json(w.gamma_minus);
    if (!w.u_minus.empty())
        j["u_minus"] = to_json(w.u_minus);
    if (!w.none) {
        j["modes"] = Json::array({w.mode_a, w.mode_b});
        j["impulses"] = Json::array({to_json(w.lambda_a), to_json(w.lambda_b)});
        j["gamma_plus"] = Json::array({to_json(w.gamma_a), to_json(w.gamma_b)});
        if (!w.u_a.empty())
            j["u_plus"] = Json::array({to_json(w.u_a), to_json(w.u_b)});
    }
    return j;
}

namespace {

constexpr const char* kEmptyPieces = "\"pieces\": []";

// An entry of a top-level array of the law file: the object's 2-space text, indented by 4.
std::string entry_text(const nlohmann::ordered_json& j) {
    const std::string text = j.dump(2);
    std::string out = "    ";
    for (const char ch : text) {
        out += ch;
        if (ch == '\n')
            out += "    ";
    }
    return out;
}

// The law's text with empty pieces and no identities: where "pieces" goes, and what follows it.
std::pair<std::string, std::string> split_at_pieces(Law law) {
    law.pieces.clear();
    law.identities.clear();
    const std::string text = law_file_text(law);
    const auto at = text.find(kEmptyPieces);
    if (at == std::string::npos)
        throw std::logic_error("LawTextWriter: no \"pieces\" in the law's text");
    return {text.substr(0, at), text.substr(at + std::string(kEmptyPieces).size())};
}

} // namespace

LawTextWriter::LawTextWriter(std::ostream& out, const Law& head) : out_(out) {
    prefix_ = split_at_pieces(head).first;
    out_ << prefix_ << "\"pieces\": [";
}

void LawTextWriter::piece(const PieceDecl& piece) {
    if (identities_ || finished_)
        throw std::logic_error("LawTextWriter: a piece after the identities");
    out_ << (pieces_++ ? ",\n" : "\n") << entry_text(piece_to_json(piece));
}

void LawTextWriter::close_pieces() { out_ << (pieces_ ? "\n  ]" : "]"); }

void LawTextWriter::identity(const IdentityDecl& identity) {
    if (finished_)
        throw std::logic_error("LawTextWriter: an identity after the end");
    if (!identities_) {
        close_pieces();
        out_ << ",\n  \"identities\": [";
    }
    out_ << (identities_++ ? ",\n" : "\n") << entry_text(identity_to_json(identity));
}

void LawTextWriter::finish(Law tail) {
    if (finished_)
        throw std::logic_error("LawTextWriter: finished twice");
    if (identities_)
        out_ << "\n  ]";
    else
        close_pieces();
    const auto [prefix, suffix] = split_at_pieces(std::move(tail));
    if (prefix != prefix_)
        throw std::logic_error("LawTextWriter: the tail's head is not the head written");
    out_ << suffix;
    finished_ = true;
}

} // namespace impactcert
