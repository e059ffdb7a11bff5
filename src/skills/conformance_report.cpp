#include "skills/conformance_report.hpp"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace skillcell::skills {

std::string_view name(Verdict verdict) {
    switch (verdict) {
        case Verdict::Pass:
            return "PASS";
        case Verdict::Warn:
            return "WARN";
        case Verdict::Fail:
            return "FAIL";
    }
    return "?";
}

void ConformanceReport::add(Finding finding) {
    findings_.push_back(std::move(finding));
    if (listener_) listener_(findings_.back());
}

void ConformanceReport::pass(std::string subject, std::string check, std::string found) {
    add(Finding{Verdict::Pass, std::move(subject), std::move(check), {}, std::move(found)});
}

void ConformanceReport::warn(std::string subject, std::string check, std::string expected,
                             std::string found) {
    add(Finding{Verdict::Warn, std::move(subject), std::move(check), std::move(expected),
                std::move(found)});
}

void ConformanceReport::fail(std::string subject, std::string check, std::string expected,
                             std::string found) {
    add(Finding{Verdict::Fail, std::move(subject), std::move(check), std::move(expected),
                std::move(found)});
}

std::size_t ConformanceReport::count(Verdict verdict) const {
    return static_cast<std::size_t>(
        std::count_if(findings_.begin(), findings_.end(),
                      [verdict](const Finding& f) { return f.verdict == verdict; }));
}

bool ConformanceReport::passed(bool strict) const {
    return count(Verdict::Fail) == 0 && (!strict || count(Verdict::Warn) == 0);
}

std::string formatFinding(const Finding& finding) {
    std::string line(name(finding.verdict));
    line += "  ";
    line += finding.subject;
    line += "  ";
    line += finding.check;
    line += ": ";
    if (finding.verdict == Verdict::Pass || finding.expected.empty()) {
        line += finding.found;
    } else {
        line += "expected ";
        line += finding.expected;
        line += ", found ";
        line += finding.found;
    }
    return line;
}

namespace {

std::string plural(std::size_t n, std::string_view one, std::string_view many) {
    return std::to_string(n) + " " + std::string(n == 1 ? one : many);
}

}  // namespace

std::string formatSummary(const ConformanceReport& report, bool strict) {
    const std::size_t passes = report.count(Verdict::Pass);
    const std::size_t warnings = report.count(Verdict::Warn);
    const std::size_t failures = report.count(Verdict::Fail);
    std::string s = plural(report.skills().size(), "skill", "skills") + ", " +
                    plural(report.findings().size(), "check", "checks") + ": " +
                    std::to_string(passes) + " passed, " + plural(warnings, "warning", "warnings") +
                    ", " + std::to_string(failures) + " failed\n";
    s += report.passed(strict) ? "RESULT: PASS" : "RESULT: FAIL";
    if (!report.passed(strict) && failures == 0) s += " (warnings count as failures: --strict)";
    return s;
}

std::string toJson(const ConformanceReport& report, bool strict) {
    nlohmann::ordered_json j;
    j["endpoint"] = report.endpoint();
    j["result"] = report.passed(strict) ? "PASS" : "FAIL";
    j["counts"] = {{"pass", report.count(Verdict::Pass)},
                   {"warn", report.count(Verdict::Warn)},
                   {"fail", report.count(Verdict::Fail)}};
    j["skills"] = nlohmann::ordered_json::array();
    for (const auto& skill : report.skills()) {
        j["skills"].push_back(
            {{"path", skill.path}, {"nodeId", skill.nodeId}, {"type", skill.type}});
    }
    j["findings"] = nlohmann::ordered_json::array();
    for (const auto& f : report.findings()) {
        j["findings"].push_back({{"verdict", name(f.verdict)},
                                 {"subject", f.subject},
                                 {"check", f.check},
                                 {"expected", f.expected},
                                 {"found", f.found}});
    }
    // Servers send any bytes: what is not UTF-8 is replaced, not thrown at the reader.
    return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

}  // namespace skillcell::skills
