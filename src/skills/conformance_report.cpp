#include "skills/conformance_report.hpp"

#include "ua/types/to_string.hpp"

#include <algorithm>
#include <cstdio>

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
    std::string s = "{\n  \"endpoint\": " + ua::jsonQuoted(report.endpoint()) + ",\n";
    s += "  \"result\": ";
    s += report.passed(strict) ? "\"PASS\"" : "\"FAIL\"";
    s += ",\n  \"counts\": {\"pass\": " + std::to_string(report.count(Verdict::Pass)) +
         ", \"warn\": " + std::to_string(report.count(Verdict::Warn)) +
         ", \"fail\": " + std::to_string(report.count(Verdict::Fail)) + "},\n";
    s += "  \"skills\": [";
    const char* sep = "\n";
    for (const auto& skill : report.skills()) {
        s += sep;
        s += "    {\"path\": " + ua::jsonQuoted(skill.path) +
             ", \"nodeId\": " + ua::jsonQuoted(skill.nodeId) +
             ", \"type\": " + ua::jsonQuoted(skill.type) + "}";
        sep = ",\n";
    }
    s += report.skills().empty() ? "],\n" : "\n  ],\n";
    s += "  \"findings\": [";
    sep = "\n";
    for (const auto& f : report.findings()) {
        s += sep;
        s += "    {\"verdict\": " + ua::jsonQuoted(name(f.verdict)) +
             ", \"subject\": " + ua::jsonQuoted(f.subject) +
             ", \"check\": " + ua::jsonQuoted(f.check) +
             ", \"expected\": " + ua::jsonQuoted(f.expected) +
             ", \"found\": " + ua::jsonQuoted(f.found) + "}";
        sep = ",\n";
    }
    s += report.findings().empty() ? "]\n}\n" : "\n  ]\n}\n";
    return s;
}

}  // namespace skillcell::skills
