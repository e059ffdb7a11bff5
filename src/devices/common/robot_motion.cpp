#include "devices/common/robot_motion.hpp"

#include "devices/common/frame.hpp"
#include "skills/reservation_client.hpp"

namespace skillcell::devices {

RobotMotion::~RobotMotion() = default;

asio::awaitable<std::unique_ptr<RobotMotion>> RobotMotion::open(
    asio::any_io_executor executor, std::string endpoint, ua::ClientConfig config, std::string& why,
    bool forceLimited, std::chrono::milliseconds patience, bool* unreachable) {
    auto motion = std::make_unique<RobotMotion>(Token{});
    std::string linearType = "CartesianLinearMoveSkillType";
    auto linear =
        co_await skills::SkillConnection::open(executor, endpoint, linearType, config, &why);
    if (!linear) {
        if (unreachable != nullptr) *unreachable = true;
        co_return nullptr;
    }
    motion->linear_ = std::move(*linear);
    // The robot's other moves over the same session: one handshake and one browse a robot.
    std::string ignored;
    auto ptp = co_await motion->linear_->alongside("CartesianPtpMoveSkillType", &ignored);
    if (ptp) motion->ptp_ = std::move(*ptp);
    if (forceLimited) {
        auto opened = co_await motion->linear_->alongside(
            "CartesianForceLimitedLinearMoveSkillType", &ignored);
        if (opened) motion->forceLimited_ = std::move(*opened);
    }
    std::vector<ua::Client*> sessions{&motion->linear_->client()};
    const skills::Hold held =
        co_await skills::hold(std::move(sessions), config.applicationUri, patience);
    if (!held.refusal.empty()) {
        why = "the robot at " + endpoint + " cannot be driven: " + held.refusal;
        // A refusal because the robot went between connect and Reserve is a lost robot (its
        // supervisor starts it again), not one that another holds.
        if (unreachable != nullptr && !motion->connected()) *unreachable = true;
        co_await motion->close();
        co_return nullptr;
    }
    motion->token_ = held.token;
    co_return motion;
}

asio::awaitable<std::string> RobotMotion::moveTo(skills::SubSkillRunner& runner, KDL::Frame flange,
                                                 Path path, std::chrono::milliseconds timeout,
                                                 MoveLimits limits) {
    if (path == Path::ForceLimited && !forceLimited_) {
        co_return "the robot at " + linear_->endpointUrl() +
            " offers no CartesianForceLimitedLinearMove: it senses no force";
    }
    skills::SkillConnection& move = path == Path::ForceLimited         ? *forceLimited_
                                    : (path == Path::Transfer && ptp_) ? *ptp_
                                                                       : *linear_;
    std::map<std::string, ua::Variant> parameters;
    if (path == Path::ForceLimited) parameters["ForceLimit"] = ua::Variant(limits.force);
    if (path != Path::Transfer && limits.velocity > 0) {
        parameters["MaxVelocity"] = ua::Variant(limits.velocity);
    }
    parameters["TargetPosition"] = frameToVariant(flange);
    parameters["ToolFrame"] = frameToVariant(KDL::Frame::Identity());
    const skills::SkillOutcome outcome =
        co_await runner.run(move.skill(), std::move(parameters), timeout);
    if (outcome.ok()) co_return std::string();
    co_return "the move to " + describe(flange) + " (" + move.description().browsePathString() +
        " at " + move.endpointUrl() + ") ended " + describeOutcome(outcome);
}

bool RobotMotion::connected() {
    return linear_->client().isConnected();
}

asio::awaitable<ua::Result<KDL::Frame>> RobotMotion::reachCentre() {
    const auto value = co_await linear_->readParameter("ReachCentre");
    if (!value) co_return value.status();
    co_return frameFromVariant(*value);
}

asio::awaitable<void> RobotMotion::close() {
    if (token_) {
        const std::uint64_t token = *token_;
        token_.reset();
        // Refused only when another took it over meanwhile: it is theirs then.
        (void)co_await skills::release(linear_->client(), token);
    }
    if (ptp_) co_await ptp_->close();
    if (forceLimited_) co_await forceLimited_->close();
    co_await linear_->close();
}

std::string describeOutcome(const skills::SkillOutcome& outcome) {
    std::string text(skills::name(outcome.kind));
    if (!outcome.reason.empty()) text += ": " + outcome.reason;
    if (outcome.status.isBad()) text += " (" + std::string(ua::statusName(outcome.status)) + ")";
    return text;
}

}  // namespace skillcell::devices
