#include "devices/world/world_link.hpp"

#include <spdlog/spdlog.h>

#include "devices/common/frame.hpp"
#include "devices/world/world_nodes.hpp"
#include "ua/address_space/ns0_ids.hpp"
#include "ua/types/connection_loss.hpp"

namespace skillcell::devices {

ua::Result<std::unique_ptr<WorldLink>> WorldLink::connect(const std::string& url,
                                                          ua::ClientConfig config,
                                                          std::string robot) {
    auto link = std::make_unique<WorldLink>(Token{}, std::move(robot));
    link->url_ = url;
    link->config_ = std::move(config);
    if (const auto s = link->open(); s.isBad()) return s;
    return link;
}

ua::StatusCode WorldLink::open() {
    if (const auto s = client_.connect(url_, config_); s.isBad()) return s;
    const auto namespaces = client_.readValue(ua::NodeId(ua::ns0::Server_NamespaceArray));
    if (!namespaces) return namespaces.status();
    const auto& uris = namespaces->elements();
    for (std::size_t i = 0; i < uris.size(); ++i) {
        const auto* uri = std::get_if<ua::String>(&uris[i]);
        if (uri != nullptr && *uri == kWorldNamespaceUri) {
            ns_ = static_cast<std::uint16_t>(i);
            ++connections_;
            return ua::status::Good;
        }
    }
    return ua::status::BadNotFound;
}

namespace {

/// The world closed the session (it outlived its timeout unused), and the channel is up.
bool sessionClosedBy(ua::StatusCode s) {
    return s == ua::status::BadSessionIdInvalid || s == ua::status::BadSessionClosed;
}

}  // namespace

bool WorldLink::connected() {
    return !lost_ && client_.isConnected();
}

void WorldLink::reconnectIfLost() {
    if (!lost_) return;
    const std::lock_guard lock(reconnectMutex_);
    if (!lost_) return;  // another thread reconnected meanwhile
    // The channel outlives a closed session: the client must let it go to open another.
    if (sessionClosed_.exchange(false)) (void)client_.disconnect();
    const auto s = open();
    // BadInvalidState: still connected (a late failure of a call on the old connection).
    if (s.isGood() || s == ua::status::BadInvalidState) lost_ = false;
}

void WorldLink::note(ua::StatusCode s) {
    if (sessionClosedBy(s)) sessionClosed_ = true;
    if (ua::isConnectionLoss(s)) lost_ = true;
    if (ua::isTransient(s)) lostSinceMark_ = true;
}

WorldLink::~WorldLink() {
    {
        const std::lock_guard lock(backlogMutex_);
        stopping_ = true;
    }
    backlogChanged_.notify_all();
    if (backlogThread_.joinable()) backlogThread_.join();
}

void WorldLink::tell(std::function<ua::StatusCode()> event, std::string what) {
    // Under the lock throughout: events told from several threads keep their order.
    const std::lock_guard lock(backlogMutex_);
    if (!backlog_.empty()) {  // after those still waiting
        backlog_.push_back({std::move(event), std::move(what), std::chrono::steady_clock::now()});
        return;
    }
    // Behind from before the call: a device asked while it travels waits for its answer.
    behind_ = true;
    const ua::StatusCode s = event();
    if (!ua::isTransient(s)) {
        if (s.isBad()) spdlog::warn("world model refused the {}: {}", what, ua::statusName(s));
        behind_ = false;
        return;
    }
    spdlog::warn("world model: the {} is not heard ({}): telling it again until it is", what,
                 ua::statusName(s));
    backlog_.push_back({std::move(event), std::move(what), std::chrono::steady_clock::now()});
    if (!backlogThread_.joinable()) backlogThread_ = std::thread([this] { deliverBacklog(); });
    backlogChanged_.notify_all();
}

void WorldLink::deliverBacklog() {
    constexpr auto kPause = std::chrono::milliseconds(100);
    constexpr auto kPatience = std::chrono::minutes(1);
    std::unique_lock lock(backlogMutex_);
    for (;;) {
        backlogChanged_.wait(lock, [this] { return stopping_ || !backlog_.empty(); });
        if (stopping_) return;
        Told& next = backlog_.front();
        lock.unlock();
        const ua::StatusCode s = next.event();  // only this thread takes from the front
        lock.lock();
        const bool late = std::chrono::steady_clock::now() - next.since > kPatience;
        if (!ua::isTransient(s) || late) {
            if (s.isGood()) {
                spdlog::info("world model: the {} is heard", next.what);
            } else {
                spdlog::warn("world model: the {}: {}{}", next.what, ua::statusName(s),
                             late ? ", given up after a minute" : "");
            }
            backlog_.pop_front();
            behind_ = !backlog_.empty();
            backlogChanged_.notify_all();  // waitUntilHeard()
            continue;
        }
        backlogChanged_.wait_for(lock, kPause, [this] { return stopping_; });
    }
}

bool WorldLink::waitUntilHeard(std::chrono::milliseconds patience) {
    std::unique_lock lock(backlogMutex_);
    return backlogChanged_.wait_for(lock, patience, [this] {
        return stopping_ || backlog_.empty();
    }) && backlog_.empty();
}

void WorldLink::heardAfter(int tries, ua::StatusCode s) {
    spdlog::info("world model: heard after {} tries ({})", tries, ua::statusName(s));
}

template <class Request>
auto WorldLink::onSession(const Request& request) -> decltype(request()) {
    reconnectIfLost();
    auto result = request();
    if (sessionClosedBy(result.status())) {
        // A device idle for longer than the session's timeout (a tool changer between tool
        // changes): the world refused the request unrun, so it goes again on a new session.
        spdlog::info("world model: the session was closed ({}); opening another",
                     ua::statusName(result.status()));
        sessionClosed_ = true;  // not a loss the device must know of, unless this fails too
        lost_ = true;
        reconnectIfLost();
        result = request();
    }
    note(result.status());
    return result;
}

ua::Result<ua::Variant> WorldLink::readValue(const std::string& path) {
    return onSession([&] { return client_.readValue(id(path)); });
}

ua::Result<std::vector<ua::Variant>> WorldLink::call(const char* method,
                                                     std::vector<ua::Variant> in) {
    return onSession(
        [&] { return client_.call(id("World"), id(std::string("World.") + method), in); });
}

ua::Result<std::vector<ua::Variant>> WorldLink::robotCall(const char* method,
                                                          std::vector<ua::Variant> in) {
    // A device started without its robot's id cannot act for one.
    if (robot_.empty()) return ua::status::BadInvalidState;
    in.insert(in.begin(), ua::Variant(ua::String(robot_)));
    return call(method, std::move(in));
}

std::string WorldLink::robotPath(const char* name) const {
    return "World/Robots/" + robot_ + "/" + name;
}

ua::StatusCode WorldLink::setFlangePose(const KDL::Frame& flange, double* contactForce) {
    const auto out = robotCall("SetFlangePose", {frameToVariant(flange)});
    if (!out) return out.status();
    if (contactForce != nullptr) {
        const double* force = out->size() == 1 ? (*out)[0].get<double>() : nullptr;
        if (force == nullptr) return ua::status::BadTypeMismatch;
        *contactForce = *force;
    }
    return ua::status::Good;
}
ua::StatusCode WorldLink::mountTool(const std::string& dockId) {
    return statusOf(robotCall("MountTool", {ua::Variant(ua::String(dockId))}));
}
ua::StatusCode WorldLink::unmountTool(const std::string& dockId) {
    return statusOf(robotCall("UnmountTool", {ua::Variant(ua::String(dockId))}));
}
ua::StatusCode WorldLink::grasp(const std::string& objectId) {
    return statusOf(robotCall("Grasp", {ua::Variant(ua::String(objectId))}));
}
ua::StatusCode WorldLink::release() {
    return statusOf(robotCall("Release"));
}

ua::StatusCode WorldLink::addObject(const std::string& objectId, const std::array<double, 3>& size,
                                    const KDL::Frame& pose) {
    return statusOf(call(
        "AddObject",
        {ua::Variant(ua::String(objectId)),
         ua::Variant::array(std::vector<double>(size.begin(), size.end())), frameToVariant(pose)}));
}
ua::StatusCode WorldLink::addTerminalBlock(const std::string& objectId,
                                           const std::array<double, 3>& size,
                                           const KDL::Frame& pose) {
    return statusOf(call(
        "AddTerminalBlock",
        {ua::Variant(ua::String(objectId)),
         ua::Variant::array(std::vector<double>(size.begin(), size.end())), frameToVariant(pose)}));
}
ua::StatusCode WorldLink::addRail(const std::string& railId, const KDL::Frame& pose, double length,
                                  double width) {
    return statusOf(call("AddRail", {ua::Variant(ua::String(railId)), frameToVariant(pose),
                                     ua::Variant(length), ua::Variant(width)}));
}
ua::StatusCode WorldLink::addFuse(const std::string& fuseId, const std::array<double, 3>& size,
                                  const KDL::Frame& pose) {
    return statusOf(call(
        "AddFuse",
        {ua::Variant(ua::String(fuseId)),
         ua::Variant::array(std::vector<double>(size.begin(), size.end())), frameToVariant(pose)}));
}
ua::StatusCode WorldLink::addFuseSlot(const std::string& slotId, const KDL::Frame& pose,
                                      double depth) {
    return statusOf(call("AddFuseSlot", {ua::Variant(ua::String(slotId)), frameToVariant(pose),
                                         ua::Variant(depth)}));
}
ua::StatusCode WorldLink::addDock(const std::string& dockId, const KDL::Frame& pose) {
    return statusOf(call("AddDock", {ua::Variant(ua::String(dockId)), frameToVariant(pose)}));
}
ua::StatusCode WorldLink::addTool(const std::string& toolId, const std::string& dockId,
                                  const KDL::Frame& gripPoint) {
    return statusOf(call("AddTool", {ua::Variant(ua::String(toolId)),
                                     ua::Variant(ua::String(dockId)), frameToVariant(gripPoint)}));
}

ua::StatusCode WorldLink::addRobot(const std::string& robotId, const KDL::Frame& base) {
    return statusOf(call("AddRobot", {ua::Variant(ua::String(robotId)), frameToVariant(base)}));
}

ua::StatusCode WorldLink::moveTool(const std::string& toolId, const std::string& dockId) {
    return statusOf(
        call("MoveTool", {ua::Variant(ua::String(toolId)), ua::Variant(ua::String(dockId))}));
}

ua::Result<std::optional<WorldLink::Found>> WorldLink::objectAtGripPoint() {
    const auto out = robotCall("ObjectAtGripPoint");
    if (!out) return out.status();
    if (out->size() != 2) return ua::status::BadTypeMismatch;
    const auto* objectId = (*out)[0].get<ua::String>();
    const auto& extent = (*out)[1];
    if (objectId == nullptr || !extent.isArray() || extent.elements().size() != 3) {
        return ua::status::BadTypeMismatch;
    }
    if (objectId->empty()) return std::optional<Found>();
    Found found{*objectId, {}};
    for (std::size_t i = 0; i < 3; ++i) {
        const double* d = std::get_if<double>(&extent.elements()[i]);
        if (d == nullptr) return ua::status::BadTypeMismatch;
        found.extent[i] = *d;
    }
    return std::optional<Found>(std::move(found));
}

ua::Result<std::string> WorldLink::dockAtFlange() {
    const auto out = robotCall("DockAtFlange");
    if (!out) return out.status();
    const auto* dockId = out->size() == 1 ? (*out)[0].get<ua::String>() : nullptr;
    if (dockId == nullptr) return ua::status::BadTypeMismatch;
    return std::string(*dockId);
}

ua::Result<KDL::Frame> WorldLink::readFrame(const std::string& path) {
    const auto value = readValue(path);
    if (!value) return value.status();
    return frameFromVariant(*value);
}

ua::Result<KDL::Frame> WorldLink::objectPose(const std::string& objectId) {
    return readFrame("World/Objects/" + objectId + "/Pose");
}

ua::Result<KDL::Frame> WorldLink::flangePose() {
    return readFrame(robotPath("FlangePose"));
}

ua::Result<KDL::Frame> WorldLink::gripPoint() {
    return readFrame(robotPath("GripPoint"));
}

ua::Result<KDL::Frame> WorldLink::dockPose(const std::string& dockId) {
    return readFrame("World/Docks/" + dockId + "/Pose");
}

ua::Result<std::string> WorldLink::dockTool(const std::string& dockId) {
    return readString("World/Docks/" + dockId + "/Tool");
}

ua::Result<std::vector<std::string>> WorldLink::children(const std::string& path) {
    auto found = onSession([&] { return client_.browse(id(path)); });
    if (!found) return found.status();
    if (found->statusCode.isBad()) return found->statusCode;
    std::vector<std::string> names;
    for (const auto& r : found->references) {
        if (r.isForward && r.nodeClass == ua::NodeClass::Object) {
            names.push_back(r.browseName.name);
        }
    }
    return names;
}

ua::Result<std::vector<std::string>> WorldLink::objectIds() {
    return children("World/Objects");
}

ua::Result<std::uint32_t> WorldLink::objectGrasps(const std::string& objectId) {
    const auto value = readValue("World/Objects/" + objectId + "/Grasps");
    if (!value) return value.status();
    const std::uint32_t* n = value->get<std::uint32_t>();
    if (n == nullptr) return ua::status::BadTypeMismatch;
    return *n;
}

ua::Result<std::vector<WorldLink::RobotView>> WorldLink::robots() {
    const auto ids = children("World/Robots");
    if (!ids) return ids.status();
    std::vector<RobotView> views;
    for (const auto& robot : *ids) {
        const std::string path = "World/Robots/" + robot + "/";
        RobotView v;
        v.id = robot;
        auto base = readFrame(path + "Base");
        if (!base) return base.status();
        auto flange = readFrame(path + "FlangePose");
        if (!flange) return flange.status();
        auto held = readString(path + "GraspedObject");
        if (!held) return held.status();
        v.base = *base;
        v.flange = *flange;
        v.held = std::move(*held);
        views.push_back(std::move(v));
    }
    return views;
}

ua::Result<std::vector<std::string>> WorldLink::dockIds() {
    return children("World/Docks");
}

ua::Result<std::array<double, 3>> WorldLink::objectSize(const std::string& objectId) {
    const auto value = readValue("World/Objects/" + objectId + "/Size");
    if (!value) return value.status();
    if (!value->isArray() || value->elements().size() != 3) return ua::status::BadTypeMismatch;
    std::array<double, 3> size{};
    for (std::size_t i = 0; i < 3; ++i) {
        const double* d = std::get_if<double>(&value->elements()[i]);
        if (d == nullptr) return ua::status::BadTypeMismatch;
        size[i] = *d;
    }
    return size;
}

ua::Result<std::string> WorldLink::readString(const std::string& path) {
    const auto value = readValue(path);
    if (!value) return value.status();
    const auto* s = value->get<ua::String>();
    if (s == nullptr) return ua::status::BadTypeMismatch;
    return *s;
}
ua::Result<double> WorldLink::readDouble(const std::string& path) {
    const auto value = readValue(path);
    if (!value) return value.status();
    const auto* d = value->get<double>();
    if (d == nullptr) return ua::status::BadTypeMismatch;
    return *d;
}

ua::Result<WorldLink::Rail> WorldLink::rail(const std::string& railId) {
    const std::string path = "World/Rails/" + railId;
    const auto pose = readFrame(path + "/Pose");
    if (!pose) return pose.status();
    const auto length = readDouble(path + "/Length");
    if (!length) return length.status();
    const auto width = readDouble(path + "/Width");
    if (!width) return width.status();
    return Rail{*pose, *length, *width};
}

ua::Result<std::vector<std::string>> WorldLink::railIds() {
    return children("World/Rails");
}

ua::Result<std::optional<WorldLink::Mount>> WorldLink::railMount(const std::string& objectId) {
    const std::string path = "World/Objects/" + objectId;
    const auto railId = readString(path + "/Rail");
    if (!railId) return railId.status();
    if (railId->empty()) return std::optional<Mount>();
    const auto position = readDouble(path + "/RailPosition");
    if (!position) return position.status();
    return std::optional<Mount>(Mount{*railId, *position});
}

ua::Result<std::string> WorldLink::railRefusal(const std::string& blockId) {
    return readString("World/Objects/" + blockId + "/RailRefusal");
}

ua::Result<WorldLink::Slot> WorldLink::fuseSlot(const std::string& slotId) {
    const std::string path = "World/FuseSlots/" + slotId;
    const auto pose = readFrame(path + "/Pose");
    if (!pose) return pose.status();
    const auto depth = readDouble(path + "/Depth");
    if (!depth) return depth.status();
    const auto fuse = readString(path + "/Fuse");
    if (!fuse) return fuse.status();
    return Slot{*pose, *depth, *fuse};
}

ua::Result<std::string> WorldLink::fuseSeat(const std::string& fuseId) {
    return readString("World/Objects/" + fuseId + "/Slot");
}

ua::Result<double> WorldLink::contactForce() {
    return readDouble(robotPath("ContactForce"));
}

ua::Result<std::string> WorldLink::mountedTool() {
    return readString(robotPath("MountedTool"));
}
ua::Result<std::string> WorldLink::graspedObject() {
    return readString(robotPath("GraspedObject"));
}

}  // namespace skillcell::devices
