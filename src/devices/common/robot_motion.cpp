#include "devices/common/robot_motion.hpp"

#include "devices/common/frame.hpp"

namespace skillcell::devices {

RobotMotion::~RobotMotion() = default;

asio::awaitable<std::unique_ptr<RobotMotion>> RobotMotion::open(asio::any_io_executor executor,
                                                                std::string endpoint,
                                                                ua::ClientConfig config,
                                                                std::string& why) {
    auto motion = std::make_unique<RobotMotion>(Token{});
    std::string linearType = "CartesianLinearMoveSkillType";
    auto linear =
        co_await skills::SkillConnection::open(executor, endpoint, linearType, config, &why);
    if (!linear) co_return nullptr;
    motion->linear_ = std::move(*linear);
    std::string ptpType = "CartesianPtpMoveSkillType";
    std::string ignored;
    auto ptp =
        co_await skills::SkillConnection::open(executor, endpoint, ptpType, config, &ignored);
    if (ptp) motion->ptp_ = std::move(*ptp);
    co_return motion;
}

asio::awaitable<std::string> RobotMotion::moveTo(skills::SubSkillRunner& runner, KDL::Frame flange,
                                                 Path path, std::chrono::milliseconds timeout) {
    skills::SkillConnection& move = (path == Path::Transfer && ptp_) ? *ptp_ : *linear_;
    std::map<std::string, ua::Variant> parameters;
    parameters["TargetPosition"] = frameToVariant(flange);
    parameters["ToolFrame"] = frameToVariant(KDL::Frame::Identity());
    const skills::SkillOutcome outcome =
        co_await runner.run(move.skill(), std::move(parameters), timeout);
    if (outcome.ok()) co_return std::string();
    co_return "the move to " + describe(flange) + " (" + move.description().browsePathString() +
        " at " + move.endpointUrl() + ") ended " + describeOutcome(outcome);
}

asio::awaitable<void> RobotMotion::close() {
    if (ptp_) co_await ptp_->close();
    co_await linear_->close();
}

std::string describeOutcome(const skills::SkillOutcome& outcome) {
    std::string text(skills::name(outcome.kind));
    if (!outcome.reason.empty()) text += ": " + outcome.reason;
    if (outcome.status.isBad()) text += " (" + std::string(ua::statusName(outcome.status)) + ")";
    return text;
}

}  // namespace skillcell::devices
