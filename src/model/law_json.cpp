// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/law_json.hpp"

#include "base/json_read.hpp"
#include "model/scene.hpp"

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <tuple>
#include <vector>

namespace impactcert {

using ReadJson = nlohmann::json;

namespace {

// ---------------------------------------------------------------------------------------------
// Syntax: nlohmann::json plus a duplicate-key check (a repeated key would silently replace the
// first one, which is exactly the kind of typo that must not skip a check).

struct Frame {
    bool object = false;
    std::string key;             // object: the current key
    std::size_t index = 0;       // array: the index of the next element
    std::set<std::string> keys;  // object: keys seen
};

std::string frames_path(const std::vector<Frame>& stack) {
    std::string path = "$";
    for (std::size_t i = 0; i + 1 < stack.size(); ++i) {
        const Frame& f = stack[i];
        if (f.object) {
            path += '.';
            path += f.key;
        } else {
            path += '[';
            path += std::to_string(f.index - 1);
            path += ']';
        }
    }
    return path;
}

// Keys and depth are checked in a first pass by a SAX handler that builds nothing; the document is
// then parsed without a callback (nlohmann's callback parser rescans the enclosing array at the
// end of every object: quadratic in the number of pieces of a law).
class SyntaxCheck {
  public:
    bool null() { return element_begins(); }
    bool boolean(bool) { return element_begins(); }
    bool number_integer(ReadJson::number_integer_t) { return element_begins(); }
    bool number_unsigned(ReadJson::number_unsigned_t) { return element_begins(); }
    bool number_float(ReadJson::number_float_t, const ReadJson::string_t&) { return element_begins(); }
    bool string(ReadJson::string_t&) { return element_begins(); }
    bool binary(ReadJson::binary_t&) { return element_begins(); }
    bool start_object(std::size_t) { return open(true); }
    bool start_array(std::size_t) { return open(false); }
    bool end_object() { return close(); }
    bool end_array() { return close(); }
    bool key(ReadJson::string_t& k) {
        Frame& f = stack_.back();
        f.key = k;
        if (!f.keys.insert(f.key).second) {
            const std::string repeated = f.key;
            stack_.push_back(Frame{});
            input_error(frames_path(stack_), "duplicate key " + in_quotes(repeated));
        }
        return true;
    }
    // A syntax error: the exception ReadJson::parse would throw (turned into line:column below).
    template <class Exception> bool parse_error(std::size_t, const std::string&, const Exception& ex) { throw ex; }

  private:
    static constexpr std::size_t kMaxDepth = 64;
    std::vector<Frame> stack_;

    bool element_begins() {
        if (!stack_.empty() && !stack_.back().object)
            ++stack_.back().index;
        return true;
    }
    bool open(bool object) {
        element_begins();
        // A law is at most 4 deep; far deeper input would make recursive code (dump() in a
        // message) overflow the stack.
        if (stack_.size() >= kMaxDepth)
            input_error(frames_path(stack_), "nested more than " + std::to_string(kMaxDepth) + " levels deep");
        stack_.push_back(Frame{object, {}, 0, {}});
        return true;
    }
    bool close() {
        stack_.pop_back();
        return true;
    }
};

// "line L, column C" of a byte offset (1-based, as editors count).
std::string line_and_column(const std::string& text, std::size_t byte) {
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            col = 1;
        } else {
            ++col;
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

ReadJson parse_syntax(const std::string& text) {
    // nlohmann's reader ends the document at a NUL byte: whatever follows (a repeated key, a
    // second document) would never be read.
    if (const auto nul = text.find('\0'); nul != std::string::npos)
        throw InputError(line_and_column(text, nul) + ": malformed JSON: a NUL character (nothing may follow the end of "
                                                      "the document)");
    try {
        SyntaxCheck check;
        ReadJson::sax_parse(text, &check);
        return ReadJson::parse(text);
    } catch (const ReadJson::parse_error& e) {
        std::string what = e.what();
        if (auto p = what.find("syntax error"); p != std::string::npos)
            what = what.substr(p);
        throw InputError(line_and_column(text, e.byte > 0 ? e.byte - 1 : 0) + ": malformed JSON: " + what);
    } catch (const ReadJson::exception& e) {
        // A number beyond a double's range (1e400), which nlohmann reports as out_of_range.
        std::string what = e.what();
        if (auto p = what.find("] "); p != std::string::npos)
            what = what.substr(p + 2);
        throw InputError("malformed JSON: " + what);
    }
}

// ---------------------------------------------------------------------------------------------
// Typed access with JSON paths.

bool is_free_text_key(const std::string& k) { return k == "note" || k == "description"; }

void expect_object(const ReadJson& j, const std::string& path, std::initializer_list<const char*> allowed,
                   std::initializer_list<const char*> required) {
    if (!j.is_object())
        input_error(path, std::string("expected an object, got ") + j.type_name());
    for (const auto& item : j.items()) {
        if (is_free_text_key(item.key())) {
            if (!item.value().is_string())
                input_error(path + "." + item.key(), "free text must be a string");
            continue;
        }
        bool known = false;
        for (const char* a : allowed)
            known = known || item.key() == a;
        if (!known)
            input_error(path + "." + item.key(), "unknown key " + in_quotes(item.key()));
    }
    for (const char* r : required)
        if (!j.contains(r))
            input_error(path, std::string("missing key ") + in_quotes(r));
}

const ReadJson& expect_array(const ReadJson& j, const std::string& path) {
    if (!j.is_array())
        input_error(path, std::string("expected an array, got ") + j.type_name());
    return j;
}

std::string get_string(const ReadJson& j, const std::string& path) {
    if (!j.is_string())
        input_error(path, std::string("expected a string, got ") + j.type_name());
    return j.get<std::string>();
}

Rational get_rational(const ReadJson& j, const std::string& path) {
    std::string text;
    if (j.is_string()) {
        text = j.get<std::string>();
    } else if (j.is_number_integer()) {
        text = j.dump();
    } else if (j.is_number()) {
        input_error(path, "JSON number " + j.dump() +
                              " is not an integer (or exceeds 64 bits): write rationals as "
                              "strings, e.g. \"1\", \"-7/12\", \"0.25\"");
    } else {
        input_error(path, std::string("expected a rational (string or integer), got ") + j.type_name());
    }
    std::string why;
    auto r = parse_rational(text, &why);
    if (!r)
        input_error(path, in_quotes(text) + ": " + why);
    return *r;
}

Vector get_vector(const ReadJson& j, const std::string& path) {
    expect_array(j, path);
    Vector v;
    for (std::size_t i = 0; i < j.size(); ++i)
        v.push_back(get_rational(j[i], path + "[" + std::to_string(i) + "]"));
    return v;
}

Matrix get_matrix(const ReadJson& j, const std::string& path) {
    expect_array(j, path);
    if (j.empty())
        input_error(path, "empty matrix");
    std::vector<Vector> rows;
    for (std::size_t i = 0; i < j.size(); ++i) {
        const std::string rp = path + "[" + std::to_string(i) + "]";
        rows.push_back(get_vector(j[i], rp));
        if (rows.back().size() != rows.front().size())
            input_error(rp, "row has " + std::to_string(rows.back().size()) + " entries, row 0 has " +
                                std::to_string(rows.front().size()));
        if (rows.back().empty())
            input_error(rp, "empty row");
    }
    return Matrix::from_rows(rows);
}

int get_small_int(const ReadJson& j, const std::string& path) {
    if (!j.is_number_integer())
        input_error(path, std::string("expected an integer, got ") + j.dump());
    // Compare in the integer's own type: an unsigned above 2^63 - 1 read as signed wraps
    // (2^64 - 1 would become -1).
    const bool in_range = j.is_number_unsigned()
                              ? j.get<std::uint64_t>() <= 1000000
                              : j.get<std::int64_t>() >= -1000000 && j.get<std::int64_t>() <= 1000000;
    if (!in_range)
        input_error(path, "integer out of range: " + j.dump());
    return static_cast<int>(j.get<std::int64_t>());
}

template <class F> void for_each_element(const ReadJson& j, const std::string& path, F f) {
    expect_array(j, path);
    for (std::size_t i = 0; i < j.size(); ++i)
        f(j[i], path + "[" + std::to_string(i) + "]");
}

// The head shared by law and system files: "masses" or "M" (exactly one), "contacts".
void read_head(const ReadJson& doc, std::vector<Rational>& masses, std::optional<Matrix>& M, std::optional<Matrix>& W,
               std::vector<FrictionDecl>& friction) {
    if (doc.contains("masses") == doc.contains("M"))
        input_error("$", "needs exactly one of \"masses\" (a diagonal mass matrix) and \"M\" (a full one)");
    if (doc.contains("masses"))
        masses = get_vector(doc["masses"], "$.masses");
    else
        M = get_matrix(doc["M"], "$.M");
    if (doc.contains("contacts")) {
        const ReadJson& c = doc["contacts"];
        if (c.is_string()) {
            if (c.get<std::string>() != "chain")
                input_error("$.contacts", "expected \"chain\" or {\"W\": [...]}, got " + c.dump());
        } else {
            expect_object(c, "$.contacts", {"W", "friction"}, {"W"});
            W = get_matrix(c["W"], "$.contacts.W");
            if (c.contains("friction"))
                for_each_element(c["friction"], "$.contacts.friction", [&](const ReadJson& f, const std::string& path) {
                    expect_object(f, path, {"contact", "mu", "tangents", "restitution_tangential", "facets"},
                                  {"contact", "mu", "tangents"});
                    FrictionDecl d;
                    const int k = get_small_int(f["contact"], path + ".contact");
                    if (k < 1)
                        input_error(path + ".contact", "contacts are numbered from 1, got " + std::to_string(k));
                    d.contact = static_cast<std::size_t>(k - 1);
                    d.mu = get_rational(f["mu"], path + ".mu");
                    for_each_element(f["tangents"], path + ".tangents", [&](const ReadJson& t, const std::string& tp) {
                        d.tangents.push_back(get_vector(t, tp));
                    });
                    if (f.contains("restitution_tangential"))
                        d.restitution_tangential = get_rational(f["restitution_tangential"], path + ".restitution_tangential");
                    if (f.contains("facets")) {
                        d.facets.emplace();
                        for_each_element(f["facets"], path + ".facets", [&](const ReadJson& a, const std::string& ap) {
                            d.facets->push_back(get_vector(a, ap));
                        });
                    }
                    friction.push_back(std::move(d));
                });
        }
    }
}

// "coordinates" (optional, names only): one name per velocity and per normal contact.
void read_coordinates(const ReadJson& doc, const std::optional<Matrix>& M, const std::vector<Rational>& masses,
                      const std::optional<Matrix>& W, std::vector<std::string>& velocity_names,
                      std::vector<std::string>& contact_names) {
    if (!doc.contains("coordinates"))
        return;
    const ReadJson& co = doc["coordinates"];
    expect_object(co, "$.coordinates", {"velocities", "contacts"}, {"velocities", "contacts"});
    const std::size_t n = M ? M->rows() : masses.size();
    const std::size_t c = W ? W->cols() : (n > 0 ? n - 1 : 0);
    for (const auto& [key, into, want] : {std::make_tuple("velocities", &velocity_names, n),
                                          std::make_tuple("contacts", &contact_names, c)}) {
        const std::string at = std::string("$.coordinates.") + key;
        for_each_element(co[key], at, [&, into = into](const ReadJson& s, const std::string& path) {
            into->push_back(get_string(s, path));
        });
        if (into->size() != want)
            input_error(at, "expected " + std::to_string(want) + " names (one per " +
                                (std::string(key) == "velocities" ? "velocity" : "normal contact") + "), got " +
                                std::to_string(into->size()));
    }
}

Law parse_document(const ReadJson& doc) {
    expect_object(doc, "$",
                  {"format", "name", "masses", "M", "contacts", "coordinates", "pieces", "identities",
                   "single_impacts", "outcomes", "claims", "symmetries", "pieces_listed"},
                  {"format", "name", "pieces"});
    const std::string format = get_string(doc["format"], "$.format");
    if (format != kLawFormat)
        input_error("$.format", "expected " + in_quotes(kLawFormat) + ", got " + in_quotes(format));
    Law law;
    law.name = get_string(doc["name"], "$.name");
    if (doc.contains("description"))
        law.description = doc["description"].get<std::string>();
    else if (doc.contains("note"))
        law.description = doc["note"].get<std::string>();
    read_head(doc, law.masses, law.M, law.W, law.friction);
    read_coordinates(doc, law.M, law.masses, law.W, law.velocity_names, law.contact_names);

    for_each_element(doc["pieces"], "$.pieces", [&](const ReadJson& p, const std::string& path) {
        expect_object(p, path, {"name", "Q", "rays", "impulses"}, {"name", "Q"});
        PieceDecl decl;
        decl.name = get_string(p["name"], path + ".name");
        decl.Q = get_matrix(p["Q"], path + ".Q");
        if (p.contains("impulses"))
            decl.impulses = get_matrix(p["impulses"], path + ".impulses");
        if (p.contains("rays")) {
            std::vector<Vector> rays;
            for_each_element(p["rays"], path + ".rays", [&](const ReadJson& r, const std::string& rp) {
                rays.push_back(get_vector(r, rp));
            });
            decl.rays = rays;
        }
        law.pieces.push_back(std::move(decl));
    });

    if (doc.contains("identities"))
        for_each_element(doc["identities"], "$.identities", [&](const ReadJson& d, const std::string& path) {
            expect_object(d, path, {"lhs", "product"}, {"lhs", "product"});
            IdentityDecl decl;
            decl.lhs = get_string(d["lhs"], path + ".lhs");
            for_each_element(d["product"], path + ".product", [&](const ReadJson& f, const std::string& fp) {
                decl.product.push_back(get_string(f, fp));
            });
            law.identities.push_back(std::move(decl));
        });

    if (doc.contains("single_impacts"))
        for_each_element(doc["single_impacts"], "$.single_impacts",
                         [&](const ReadJson& d, const std::string& path) {
                             expect_object(d, path, {"piece", "contact", "restitution"},
                                           {"piece", "contact", "restitution"});
                             SingleImpactDecl decl;
                             decl.piece = get_string(d["piece"], path + ".piece");
                             decl.contact = get_small_int(d["contact"], path + ".contact");
                             decl.restitution = get_rational(d["restitution"], path + ".restitution");
                             law.single_impacts.push_back(std::move(decl));
                         });

    if (doc.contains("outcomes"))
        for_each_element(doc["outcomes"], "$.outcomes", [&](const ReadJson& d, const std::string& path) {
            expect_object(d, path, {"name", "u_minus", "u_plus"}, {"name", "u_minus", "u_plus"});
            OutcomeDecl decl;
            decl.name = get_string(d["name"], path + ".name");
            decl.u_minus = get_vector(d["u_minus"], path + ".u_minus");
            decl.u_plus = get_vector(d["u_plus"], path + ".u_plus");
            law.outcomes.push_back(std::move(decl));
        });

    if (doc.contains("symmetries"))
        for_each_element(doc["symmetries"], "$.symmetries", [&](const ReadJson& d, const std::string& path) {
            expect_object(d, path, {"name", "P", "P_prime"}, {"name", "P", "P_prime"});
            SymmetryDecl decl;
            decl.name = get_string(d["name"], path + ".name");
            decl.P = get_matrix(d["P"], path + ".P");
            decl.P_prime = get_matrix(d["P_prime"], path + ".P_prime");
            law.symmetries.push_back(std::move(decl));
        });
    if (doc.contains("pieces_listed")) {
        const std::string listed = get_string(doc["pieces_listed"], "$.pieces_listed");
        if (listed == "orbit-representatives")
            law.representatives_only = true;
        else if (listed != "all")
            input_error("$.pieces_listed", "expected \"all\" or \"orbit-representatives\", got " + in_quotes(listed));
    }

    if (doc.contains("claims")) {
        std::vector<std::string> claims;
        for_each_element(doc["claims"], "$.claims", [&](const ReadJson& d, const std::string& path) {
            claims.push_back(get_string(d, path));
        });
        law.claims = claims;
    }
    return law;
}

} // namespace

namespace json_read {
ReadJson parse_syntax(const std::string& text) { return impactcert::parse_syntax(text); }
void expect_object(const ReadJson& j, const std::string& path, std::initializer_list<const char*> allowed,
                   std::initializer_list<const char*> required) {
    impactcert::expect_object(j, path, allowed, required);
}
const ReadJson& expect_array(const ReadJson& j, const std::string& path) { return impactcert::expect_array(j, path); }
std::string get_string(const ReadJson& j, const std::string& path) { return impactcert::get_string(j, path); }
Rational get_rational(const ReadJson& j, const std::string& path) { return impactcert::get_rational(j, path); }
Vector get_vector(const ReadJson& j, const std::string& path) { return impactcert::get_vector(j, path); }
} // namespace json_read

Law parse_law_text(const std::string& text, const std::string& origin, std::size_t max_pieces, std::size_t max_memory_mb) {
    try {
        Law law = parse_document(parse_syntax(text));
        Model check(law, max_pieces, max_memory_mb); // semantic validation, with JSON paths
        return law;
    } catch (const InputError& e) {
        throw InputError(origin + ": " + e.what());
    }
}

std::string read_file_text(const std::string& path) {
    // A directory opens like a file and reads as empty ("unexpected end of input"): say so.
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw InputError(path + ": is a directory");
    errno = 0;
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw InputError(path + ": cannot read file: " + (errno ? std::strerror(errno) : "cannot open"));
    // Not `text << in.rdbuf()`: a string buffer that cannot grow ends that copy early without an
    // error, and a truncated law would be reported as malformed. Here a failed allocation is
    // std::bad_alloc (out of memory, exit 3) and a failed read is an error.
    std::string text;
    if (const auto size = std::filesystem::file_size(path, ec); !ec && size > 0) {
        if (size > text.max_size())
            throw std::bad_alloc();
        text.reserve(static_cast<std::size_t>(size));
    }
    std::vector<char> buffer(1 << 16);
    for (;;) {
        in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        text.append(buffer.data(), static_cast<std::size_t>(in.gcount()));
        if (!in)
            break;
    }
    if (in.bad() || !in.eof())
        throw InputError(path + ": cannot read file: read error");
    return text;
}

System parse_system_text(const std::string& text, const std::string& origin) {
    try {
        const ReadJson doc = parse_syntax(text);
        if (!doc.is_object())
            input_error("$", std::string("expected an object, got ") + doc.type_name());
        if (!doc.contains("format") || !doc["format"].is_string())
            input_error("$.format", "expected \"" + std::string(kSystemFormat) + "\" or \"" + kLawFormat + "\"");
        const std::string format = doc["format"].get<std::string>();
        if (format == kLawFormat) {
            // A law file names a system: its head, by the law's own rules (the law is validated whole).
            const Law law = parse_document(doc);
            Model(law, Limits{}.max_pieces);
            return System{law.name, law.masses, law.M, law.W, law.friction, {}, law.contact_names, law.velocity_names};
        }
        if (format == kSceneFormat)
            return parse_scene(doc);
        if (format != kSystemFormat)
            input_error("$.format", "expected " + in_quotes(kSystemFormat) + ", " + in_quotes(kSceneFormat) + " or " +
                                        in_quotes(kLawFormat) + ", got " + in_quotes(format));
        expect_object(doc, "$", {"format", "name", "masses", "M", "contacts", "coordinates"}, {"format", "name"});
        System s;
        s.name = get_string(doc["name"], "$.name");
        if (s.name.empty())
            input_error("$.name", "empty system name");
        read_head(doc, s.masses, s.M, s.W, s.friction);
        make_mechanics(s, Dependent::allow); // validated (dependent columns: refused by the commands that need full rank)
        read_coordinates(doc, s.M, s.masses, s.W, s.velocity_names, s.contact_names);
        return s;
    } catch (const InputError& e) {
        throw InputError(origin + ": " + e.what());
    }
}

System load_system_file(const std::string& path) {
    System s = parse_system_text(read_file_text(path), path);
    s.origin = path;
    return s;
}

Law load_law_file(const std::string& path, std::size_t max_pieces, std::size_t max_memory_mb) {
    return parse_law_text(read_file_text(path), path, max_pieces, max_memory_mb);
}

Law load_law_declaration(const std::string& path) {
    const std::string text = read_file_text(path);
    try {
        return parse_document(parse_syntax(text));
    } catch (const InputError& e) {
        throw InputError(path + ": " + e.what());
    }
}

Model load_model_file(const std::string& path, std::size_t max_pieces, std::size_t max_memory_mb) {
    const std::string text = read_file_text(path);
    try {
        return Model(parse_document(parse_syntax(text)), max_pieces, max_memory_mb); // validated once
    } catch (const InputError& e) {
        throw InputError(path + ": " + e.what());
    }
}

namespace {

nlohmann::ordered_json law_vector_json(const Vector& v) {
    nlohmann::ordered_json a = nlohmann::ordered_json::array();
    for (const auto& x : v)
        a.push_back(to_string(x));
    return a;
}

} // namespace

nlohmann::ordered_json piece_to_json(const PieceDecl& p) {
    nlohmann::ordered_json piece;
    piece["name"] = p.name;
    nlohmann::ordered_json Q = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < p.Q.rows(); ++i)
        Q.push_back(law_vector_json(p.Q.row(i)));
    piece["Q"] = Q;
    if (p.rays) {
        nlohmann::ordered_json rays = nlohmann::ordered_json::array();
        for (const auto& r : *p.rays)
            rays.push_back(law_vector_json(r));
        piece["rays"] = rays;
    }
    if (p.impulses) {
        nlohmann::ordered_json L = nlohmann::ordered_json::array();
        for (std::size_t i = 0; i < p.impulses->rows(); ++i)
            L.push_back(law_vector_json(p.impulses->row(i)));
        piece["impulses"] = L;
    }
    return piece;
}

nlohmann::ordered_json identity_to_json(const IdentityDecl& d) {
    return nlohmann::ordered_json{{"lhs", d.lhs}, {"product", d.product}};
}

nlohmann::ordered_json law_to_json(const Law& law) {
    using OJson = nlohmann::ordered_json;
    auto vec = [](const Vector& v) {
        OJson a = OJson::array();
        for (const auto& x : v)
            a.push_back(to_string(x));
        return a;
    };
    auto mat = [&](const Matrix& m) {
        OJson a = OJson::array();
        for (std::size_t i = 0; i < m.rows(); ++i)
            a.push_back(vec(m.row(i)));
        return a;
    };
    OJson out;
    out["format"] = kLawFormat;
    out["name"] = law.name;
    if (law.M)
        out["M"] = mat(*law.M);
    else
        out["masses"] = vec(law.masses);
    if (law.W) {
        out["contacts"] = OJson{{"W", mat(*law.W)}};
        if (!law.friction.empty()) {
            OJson fs = OJson::array();
            for (const auto& f : law.friction) {
                OJson tangents = OJson::array();
                for (const auto& t : f.tangents)
                    tangents.push_back(vec(t));
                OJson entry{{"contact", f.contact + 1}, {"mu", to_string(f.mu)}, {"tangents", tangents}};
                if (sign_of(f.restitution_tangential) != Sign::zero)
                    entry["restitution_tangential"] = to_string(f.restitution_tangential);
                if (f.facets) {
                    OJson facets = OJson::array();
                    for (const auto& a : *f.facets)
                        facets.push_back(vec(a));
                    entry["facets"] = facets;
                }
                fs.push_back(entry);
            }
            out["contacts"]["friction"] = fs;
        }
    } else
        out["contacts"] = "chain";
    if (!law.velocity_names.empty() || !law.contact_names.empty())
        out["coordinates"] = OJson{{"velocities", law.velocity_names}, {"contacts", law.contact_names}};
    OJson pieces = OJson::array();
    for (const auto& p : law.pieces)
        pieces.push_back(piece_to_json(p));
    out["pieces"] = pieces;
    if (!law.identities.empty()) {
        OJson ids = OJson::array();
        for (const auto& d : law.identities)
            ids.push_back(identity_to_json(d));
        out["identities"] = ids;
    }
    if (!law.single_impacts.empty()) {
        OJson sis = OJson::array();
        for (const auto& d : law.single_impacts)
            sis.push_back(OJson{{"piece", d.piece}, {"contact", d.contact},
                                {"restitution", to_string(d.restitution)}});
        out["single_impacts"] = sis;
    }
    if (!law.outcomes.empty()) {
        OJson os = OJson::array();
        for (const auto& d : law.outcomes)
            os.push_back(OJson{{"name", d.name}, {"u_minus", vec(d.u_minus)}, {"u_plus", vec(d.u_plus)}});
        out["outcomes"] = os;
    }
    if (!law.symmetries.empty()) {
        OJson syms = OJson::array();
        for (const auto& d : law.symmetries)
            syms.push_back(OJson{{"name", d.name}, {"P", mat(d.P)}, {"P_prime", mat(d.P_prime)}});
        out["symmetries"] = syms;
    }
    if (law.representatives_only)
        out["pieces_listed"] = "orbit-representatives";
    if (law.claims)
        out["claims"] = *law.claims;
    return out;
}

} // namespace impactcert
