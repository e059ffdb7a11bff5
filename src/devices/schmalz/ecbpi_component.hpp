#pragma once
// EcbpiComponent: what `skillcell device schmalz` serves: the ECBPi adapter on an IO-Link
// master port and its skills Grasp and Release (grip point VACUUM at the given offset from
// the tool mounting plate). Build and destroy it on the server's thread.
#include <memory>
#include <string>

#include "devices/gripper/gripper_skills.hpp"
#include "devices/schmalz/ecbpi_gripper.hpp"

namespace skillcell::devices::schmalz {

struct EcbpiComponentOptions {
    EcbpiComponentOptions() = default;
    /// The suction cup's face, 12 cm from the mounting plate along its z axis.
    KDL::Frame gripPointOffset = KDL::Frame(KDL::Vector(0, 0, 0.12));
    EcbpiGripperOptions gripper;
};

class EcbpiComponent {
public:
    /// `master` must outlive the component.
    [[nodiscard]] static ua::Result<std::unique_ptr<EcbpiComponent>> create(
        ua::Server& server, IoLinkMaster& master, const EcbpiComponentOptions& options,
        std::string* error = nullptr);
    ~EcbpiComponent();
    EcbpiComponent(const EcbpiComponent&) = delete;
    EcbpiComponent& operator=(const EcbpiComponent&) = delete;

    [[nodiscard]] skills::SkillServer& skills() { return *skills_; }

    struct Token {
    private:
        friend class EcbpiComponent;
        Token() = default;
    };
    explicit EcbpiComponent(Token) {}

private:
    std::unique_ptr<EcbpiGripper> gripper_;
    // After the gripper: the skills' behaviours refer to it, so they go first.
    std::unique_ptr<skills::SkillServer> skills_;
};

}  // namespace skillcell::devices::schmalz
