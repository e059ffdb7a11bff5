#pragma once
// MoveBehaviour: the four move skills of a robot arm (CartesianLinearMove,
// CartesianPtpMove, JointLinearMove, JointPtpMove) as one SkillBehaviour parameterised by
// the kind of move. Start reads the parameters, plans the whole motion and hands it to
// the ArmController; a target that cannot be reached ends the run at once as failed (the
// skill goes to Halted with the reason). Suspend, Resume and Halt pause, continue and stop
// the motion.
#include <functional>
#include <memory>

#include "devices/arm/arm_controller.hpp"
#include "devices/arm/motion_planner.hpp"
#include "skills/skill_behaviour.hpp"

namespace skillcell::devices {

class MoveBehaviour final : public skills::SkillBehaviour {
public:
    /// `onToolFrame` hears the ToolFrame of every started move (the component publishes
    /// the TCP pose with it).
    MoveBehaviour(MoveKind kind, ArmController& arm, const MotionPlanner& planner,
                  std::function<void(const KDL::Frame&)> onToolFrame = {})
        : kind_(kind), arm_(arm), planner_(planner), onToolFrame_(std::move(onToolFrame)) {}

    void start(const skills::SkillParameters& parameters, skills::SkillRun run) override;
    void suspend() override;
    void resume() override;
    void halt() override;

    /// The move request the parameters describe, or why they describe none.
    [[nodiscard]] static std::variant<MoveRequest, std::string> request(
        MoveKind kind, const skills::SkillParameters& parameters);

private:
    MoveKind kind_;
    ArmController& arm_;
    const MotionPlanner& planner_;
    std::function<void(const KDL::Frame&)> onToolFrame_;
    // This skill's motion is the arm's current one. Shared with the motion's completion,
    // which may run after this behaviour is gone.
    std::shared_ptr<bool> moving_ = std::make_shared<bool>(false);
};

}  // namespace skillcell::devices
