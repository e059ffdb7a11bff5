#pragma once
// WorkDirectory: where a running cell keeps its state: the cell CA, the users and their
// password files, each component's PKI directory, the KB's data, the MES's journal, the logs
// and `cell up`'s control socket. Given, it is kept (and reused by the next `cell up`);
// otherwise a new temporary one that goes away at the end unless kept (a failed demo keeps
// its logs).
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

namespace skillcell::apps {

class WorkDirectory {
public:
    /// `given` (created when missing, kept), or a new temporary "<prefix>-XXXXXX"; with a
    /// logs/ folder. Readable by us only: it holds keys and passwords.
    [[nodiscard]] static std::optional<WorkDirectory> create(const std::string& given,
                                                             const std::string& prefix,
                                                             std::string* error);
    WorkDirectory(WorkDirectory&& other) noexcept
        : path_(std::move(other.path_)), keep_(std::exchange(other.keep_, true)) {}
    WorkDirectory& operator=(WorkDirectory&&) = delete;
    WorkDirectory(const WorkDirectory&) = delete;
    WorkDirectory& operator=(const WorkDirectory&) = delete;
    ~WorkDirectory();

    [[nodiscard]] const std::filesystem::path& path() const { return path_; }
    /// A component's log: logs/<name>.log.
    [[nodiscard]] std::filesystem::path log(const std::string& name) const {
        return path_ / "logs" / (name + ".log");
    }
    void keep() { keep_ = true; }

private:
    WorkDirectory() = default;
    std::filesystem::path path_;
    bool keep_ = false;
};

/// Writes `text` and a newline to `file`, readable by us only (a password).
[[nodiscard]] bool writeSecret(const std::filesystem::path& file, const std::string& text);

/// The last `lines` lines of a text file (a component's log), for a report.
[[nodiscard]] std::string lastLines(const std::filesystem::path& file, std::size_t lines);

}  // namespace skillcell::apps
