#pragma once
// ConformanceReport: what the conformance checker found on one server, as a list of
// findings (PASS, WARN, FAIL), each naming the skill by its browse path, the check, and what
// was expected versus what was found. `skillcell check` prints it line by line as findings
// arrive (a listener), or as JSON at the end; its exit code comes from here.
//
// The report knows nothing of OPC UA: checks fill in text, so that the same report serves
// the terminal, scripts (JSON) and tests.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace skillcell::skills {

enum class Verdict : std::uint8_t { Pass, Warn, Fail };

/// "PASS", "WARN", "FAIL".
[[nodiscard]] std::string_view name(Verdict verdict);

struct Finding {
    Verdict verdict = Verdict::Pass;
    /// The skill's browse path from the start node ("Objects/Robot/Move"), or "server" for
    /// checks of the server's model as a whole.
    std::string subject;
    /// What was checked: a child's browse path relative to the skill ("ParameterSet/
    /// MaxVelocity"), or the name of a check ("type", "Halt in Ready").
    std::string check;
    /// What the model asks for; empty for a PASS, where `found` says what was seen.
    std::string expected;
    std::string found;
};

/// One skill the checker looked at (for the summary and the JSON report).
struct CheckedSkill {
    std::string path;    // browse path, as in Finding::subject
    std::string nodeId;  // text form, e.g. "ns=2;s=Robot.Move"
    std::string type;    // type name and NodeId, e.g. "CartesianLinearMoveSkillType (ns=3;i=1004)"
};

class ConformanceReport {
public:
    /// Called for every finding as it is added (the CLI prints lines as checks run).
    using Listener = std::function<void(const Finding&)>;

    ConformanceReport() = default;
    explicit ConformanceReport(std::string endpoint) : endpoint_(std::move(endpoint)) {}

    void setListener(Listener listener) { listener_ = std::move(listener); }
    void add(Finding finding);
    void pass(std::string subject, std::string check, std::string found);
    void warn(std::string subject, std::string check, std::string expected, std::string found);
    void fail(std::string subject, std::string check, std::string expected, std::string found);
    void addSkill(CheckedSkill skill) { skills_.push_back(std::move(skill)); }

    [[nodiscard]] const std::string& endpoint() const { return endpoint_; }
    [[nodiscard]] const std::vector<Finding>& findings() const { return findings_; }
    [[nodiscard]] const std::vector<CheckedSkill>& skills() const { return skills_; }
    [[nodiscard]] std::size_t count(Verdict verdict) const;
    /// No FAIL (warnings allowed; `strict` counts them as failures too).
    [[nodiscard]] bool passed(bool strict = false) const;
    /// The process exit code: 0 when passed, 1 otherwise (2, usage and connection errors,
    /// is the command's business: no report exists then).
    [[nodiscard]] int exitCode(bool strict = false) const { return passed(strict) ? 0 : 1; }

private:
    std::string endpoint_;
    std::vector<Finding> findings_;
    std::vector<CheckedSkill> skills_;
    Listener listener_;
};

/// One line: "PASS  Objects/Move  CurrentState: Ready (Id i=2400, Number 12)" or
/// "FAIL  Objects/Move  ParameterSet/MaxVelocity: expected DataType Double ..., found ...".
[[nodiscard]] std::string formatFinding(const Finding& finding);
/// "3 skills, 150 checks: 147 passed, 2 warnings, 1 failed" and the overall result.
[[nodiscard]] std::string formatSummary(const ConformanceReport& report, bool strict = false);
/// The whole report as a JSON document (endpoint, result, counts, skills, findings).
[[nodiscard]] std::string toJson(const ConformanceReport& report, bool strict = false);

}  // namespace skillcell::skills
