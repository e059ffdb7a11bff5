#include "ua/pki/file_util.hpp"

#include <fstream>
#include <iterator>
#include <string>

namespace skillcell::ua::pki {

std::vector<std::uint8_t> readWholeFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace skillcell::ua::pki
