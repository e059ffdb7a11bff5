#pragma once
// The dashboard's page, script and style (web/), compiled in by embed_models.cmake.
#include <string_view>
#include <vector>

namespace skillcell::dashboard {

/// The file `name` of web/ ("index.html", "app.js", ...), empty when there is none.
[[nodiscard]] std::string_view webAsset(std::string_view name);
/// Every file's name.
[[nodiscard]] std::vector<std::string_view> webAssetNames();

}  // namespace skillcell::dashboard
