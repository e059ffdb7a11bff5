#pragma once
// TempDir: a fresh directory under the system's temporary directory, removed with everything
// in it when the object goes (a test's data: a KB's Virtuoso database, a journal).
#include <filesystem>
#include <random>
#include <string>
#include <system_error>

namespace skillcell::test {

class TempDir {
public:
    /// `prefix`: the start of the directory's name ("skillcell-kb-test").
    explicit TempDir(const std::string& prefix) {
        std::random_device rd;
        path_ = std::filesystem::temp_directory_path() / (prefix + "-" + std::to_string(rd()));
        std::filesystem::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    [[nodiscard]] const std::filesystem::path& path() const { return path_; }
    /// `name` inside the directory, as a string for command lines.
    [[nodiscard]] std::string operator/(const std::string& name) const {
        return (path_ / name).string();
    }

private:
    std::filesystem::path path_;
};

}  // namespace skillcell::test
