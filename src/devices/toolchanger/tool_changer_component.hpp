#pragma once
// ToolChangerComponent: what `skillcell device toolchanger` serves: the skills AttachTool,
// DetachTool and ChangeTool over a ToolChanger, and Objects/ToolChanger/MountedTool (the
// tool the identification pin last showed). Build and destroy it on the server's thread.
#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "devices/toolchanger/tool_changer.hpp"
#include "skills/skill_server.hpp"

namespace skillcell::devices::toolchanger {

class ToolChangerComponent {
public:
    /// The companion models its skills are of: what a server process loads beside namespace
    /// 0 before it creates the component (skills::SkillServer::loadModels).
    [[nodiscard]] static std::span<const std::string_view> skillModels();
    /// `io` must outlive the component.
    [[nodiscard]] static ua::Result<std::unique_ptr<ToolChangerComponent>> create(
        ua::Server& server, ToolChangerIo& io, ToolTable tools,
        std::shared_ptr<skills::SkillDetector> detector, ToolChangerOptions options,
        std::string* error = nullptr);
    ~ToolChangerComponent();
    ToolChangerComponent(const ToolChangerComponent&) = delete;
    ToolChangerComponent& operator=(const ToolChangerComponent&) = delete;

    [[nodiscard]] skills::SkillServer& skills() { return *skills_; }
    [[nodiscard]] ToolChanger& changer() { return *changer_; }

    struct Token {
    private:
        friend class ToolChangerComponent;
        Token() = default;
    };
    explicit ToolChangerComponent(Token) {}

private:
    std::shared_ptr<ToolChanger> changer_;
    // After the changer: the skills' behaviours refer to it, so they go first.
    std::unique_ptr<skills::SkillServer> skills_;
};

}  // namespace skillcell::devices::toolchanger
