#include "work_directory.hpp"

#include <cstdlib>
#include <deque>
#include <fstream>

namespace skillcell::apps {

namespace fs = std::filesystem;

std::optional<WorkDirectory> WorkDirectory::create(const std::string& given,
                                                   const std::string& prefix, std::string* error) {
    WorkDirectory w;
    std::error_code ec;
    if (!given.empty()) {
        w.path_ = fs::absolute(given, ec);
        if (!ec) fs::create_directories(w.path_, ec);
        w.keep_ = true;
    } else {
        std::string pattern = (fs::temp_directory_path(ec) / (prefix + "-XXXXXX")).string();
        if (::mkdtemp(pattern.data()) == nullptr) {
            *error = "cannot create a directory in " + fs::temp_directory_path(ec).string();
            return std::nullopt;
        }
        w.path_ = pattern;
    }
    if (!ec) fs::permissions(w.path_, fs::perms::owner_all, ec);
    if (!ec) fs::create_directories(w.path_ / "logs", ec);
    if (ec) {
        *error = "cannot create " + w.path_.string() + ": " + ec.message();
        return std::nullopt;
    }
    return w;
}

WorkDirectory::~WorkDirectory() {
    std::error_code ec;
    if (!keep_ && !path_.empty()) fs::remove_all(path_, ec);
}

bool writeSecret(const fs::path& file, const std::string& text) {
    std::ofstream out(file, std::ios::trunc);
    std::error_code ec;
    fs::permissions(file, fs::perms::owner_read | fs::perms::owner_write, ec);
    out << text << '\n';
    return static_cast<bool>(out.flush()) && !ec;
}

std::string lastLines(const fs::path& file, std::size_t lines) {
    std::ifstream in(file);
    std::deque<std::string> kept;
    for (std::string line; std::getline(in, line);) {
        kept.push_back(std::move(line));
        if (kept.size() > lines) kept.pop_front();
    }
    std::string out;
    for (const auto& l : kept) out += l + "\n";
    return out;
}

}  // namespace skillcell::apps
