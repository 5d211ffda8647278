// cli_main.cpp -- the `impactcert` command (SPEC section 6).
//
// Exit status: 0 success / every claim proved; 1 a claim refuted; 2 bad input or usage.
// Every error is one line on stderr: "impactcert: <place>: <reason>".
#include "certificate.hpp"
#include "law_json.hpp"
#include "obligations.hpp"
#include "paper_law.hpp"
#include "report.hpp"
#include "smt.hpp"
#include "verdict_output.hpp"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace impactcert {
namespace {

constexpr int kExitProved = 0;
constexpr int kExitRefuted = 1;
constexpr int kExitBadInput = 2;

Model load_model(const std::string& law_path) {
    return Model(law_path.empty() ? paper_law() : load_law_file(law_path));
}

int run_verify(const std::string& law_path, bool json, const std::string& junit_path) {
    const Model model = load_model(law_path);
    const VerifyReport report = verify(model);
    if (json)
        std::cout << verdict_json(report).dump(2) << "\n";
    else
        std::cout << verdict_table(report, model);
    if (!junit_path.empty()) {
        std::ofstream out(junit_path, std::ios::binary);
        out << verdict_junit(report);
        if (!out)
            throw InputError(junit_path + ": cannot write the JUnit report");
    }
    return report.passed() ? kExitProved : kExitRefuted;
}

int run_certify(const std::string& law_path, const std::string& out_path) {
    const Model model = load_model(law_path);
    const VerifyReport report = verify(model);
    const std::string text = certificate_text(make_certificate(model, report));
    std::ofstream out(out_path, std::ios::binary);
    out << text;
    out.close();
    if (!out)
        throw InputError(out_path + ": cannot write the certificate");
    std::cerr << "impactcert: wrote " << out_path << " (" << report.law << ": "
              << (report.passed() ? "proved" : "refuted") << ")\n";
    return report.passed() ? kExitProved : kExitRefuted;
}

void write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    out.close();
    if (!out)
        throw InputError(path + ": cannot write");
}

int run_report(const std::string& law_path, const std::string& dir) {
    const Model model = load_model(law_path);
    const VerifyReport report = verify(model);
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        throw InputError(dir + ": cannot create directory: " + ec.message());
    write_file(dir + "/report.md", report_markdown(model, report));
    write_file(dir + "/report.html", report_html(model, report));
    std::cout << dir << "/report.md\n" << dir << "/report.html\n";
    return kExitProved; // a report is written whatever the verdict
}

int run_smt(const std::string& law_path, const std::string& dir) {
    const Model model = load_model(law_path);
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        throw InputError(dir + ": cannot create directory: " + ec.message());
    for (const auto& problem : smt_problems(model)) {
        const std::string path = dir + "/" + problem.id + ".smt2";
        std::ofstream out(path, std::ios::binary);
        out << problem.script;
        out.close();
        if (!out)
            throw InputError(path + ": cannot write");
        std::cout << path << "\n";
    }
    return kExitProved;
}

// Splits on white space and commas; parentheses and brackets are decoration.
std::vector<std::string> tokens_of(const std::string& text) {
    std::vector<std::string> out;
    std::string cur;
    for (char ch : text) {
        if (ch == ' ' || ch == '\t' || ch == ',' || ch == '(' || ch == ')' || ch == '[' ||
            ch == ']' || ch == '\r' || ch == '\n') {
            if (!cur.empty())
                out.push_back(cur);
            cur.clear();
        } else {
            cur += ch;
        }
    }
    if (!cur.empty())
        out.push_back(cur);
    return out;
}

std::string line_of(const Vector& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i)
        s += (i ? " " : "") + to_string(v[i]);
    return s;
}

// One point: c contact velocities, or n ball velocities with --velocities.
std::string evaluate_point(const Model& model, const Vector& x, bool velocities, const std::string& where) {
    const Vector gamma = velocities ? model.contact_velocities(x) : x;
    const auto values = model.values_at(gamma);
    if (values.empty())
        throw InputError(where + ": gamma- = " + to_string(gamma) + " lies in no cone of law " +
                         model.law().name);
    std::string out;
    for (std::size_t k = 0; k < values.size(); ++k) {
        const Vector shown = velocities ? model.post_impact_velocities(x, gamma, values[k]) : values[k];
        out += (k ? " | " : "") + line_of(shown);
    }
    return out;
}

int run_eval(const std::string& law_path, bool velocities, const std::vector<std::string>& args) {
    const Model model = load_model(law_path);
    const std::size_t dim = velocities ? model.balls() : model.contacts();
    auto read_point = [&](const std::vector<std::string>& toks, std::size_t first, const std::string& where) {
        Vector x;
        for (std::size_t i = first; i < first + dim; ++i) {
            std::string why;
            auto r = parse_cli_number(toks[i], &why);
            if (!r)
                throw InputError(where + ": " + toks[i] + ": " + why);
            x.push_back(*r);
        }
        return x;
    };
    if (!args.empty()) {
        std::vector<std::string> toks;
        for (const auto& a : args)
            for (auto& t : tokens_of(a))
                toks.push_back(t);
        if (toks.empty() || toks.size() % dim != 0)
            throw InputError("arguments: expected a multiple of " + std::to_string(dim) + " numbers (" +
                             (velocities ? "ball" : "contact") + " velocities), got " +
                             std::to_string(toks.size()));
        for (std::size_t first = 0; first < toks.size(); first += dim)
            std::cout << evaluate_point(model, read_point(toks, first, "arguments"), velocities,
                                        "arguments")
                      << "\n";
        return kExitProved;
    }
    std::string line;
    for (std::size_t lineno = 1; std::getline(std::cin, line); ++lineno) {
        const auto toks = tokens_of(line);
        if (toks.empty() || toks.front().front() == '#')
            continue;
        const std::string where = "stdin:" + std::to_string(lineno);
        if (toks.size() != dim)
            throw InputError(where + ": expected " + std::to_string(dim) + " numbers, got " +
                             std::to_string(toks.size()));
        std::cout << evaluate_point(model, read_point(toks, 0, where), velocities, where) << "\n";
    }
    return kExitProved;
}

} // namespace
} // namespace impactcert

int main(int argc, char** argv) {
    using namespace impactcert;
    CLI::App app{"impactcert: exact proofs for cone-wise linear impact laws"};
    app.set_version_flag("--version", std::string("impactcert ") + IMPACTCERT_VERSION);
    app.require_subcommand(1);

    std::string law_path, junit_path, out_path;
    bool json = false, velocities = false;
    std::vector<std::string> eval_args;

    auto* verify_cmd = app.add_subcommand("verify", "decide every proof obligation; exit 0 when every claim is proved, 1 when one is refuted, 2 on bad input");
    verify_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    verify_cmd->add_flag("--json", json, "print the impactcert-verdict/1 JSON instead of the table");
    verify_cmd->add_option("--junit", junit_path, "also write a JUnit XML report to this file");

    auto* certify_cmd = app.add_subcommand("certify", "write the impactcert-certificate/1 JSON; exit 0 when every claim is proved, 1 when one is refuted, 2 on bad input");
    certify_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    certify_cmd->add_option("-o,--output", out_path, "certificate file to write")->required();

    auto* report_cmd = app.add_subcommand("report", "write report.md (CI job summary) and a self-contained report.html with a picture of the cones");
    report_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    report_cmd->add_option("-o,--output", out_path, "directory to write report.md and report.html into")->required();

    auto* smt_cmd = app.add_subcommand("smt", "write one SMT-LIB2 file per universal claim (the claim negated: unsat = holds)");
    smt_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    smt_cmd->add_option("-o,--output", out_path, "directory to write the .smt2 files into")->required();

    auto* eval_cmd = app.add_subcommand("eval", "evaluate S exactly at points given as arguments or stdin lines");
    eval_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    eval_cmd->add_flag("--velocities", velocities, "points are ball velocities u- (print u+)");
    eval_cmd->add_option("points", eval_args, "numbers: rationals (-3/4), decimals (0.1), hex floats (0x1.8p-3)");

    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return 2;
    }
    try {
        if (verify_cmd->parsed())
            return run_verify(law_path, json, junit_path);
        if (certify_cmd->parsed())
            return run_certify(law_path, out_path);
        if (report_cmd->parsed())
            return run_report(law_path, out_path);
        if (smt_cmd->parsed())
            return run_smt(law_path, out_path);
        return run_eval(law_path, velocities, eval_args);
    } catch (const InputError& e) {
        std::cerr << "impactcert: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "impactcert: internal error (please report): " << e.what() << "\n";
        return 3;
    }
}
