#pragma once
// WorldConnection: a device's link to the world model (--world), opened on a thread of its
// own while the component loads its models (runServerProcess's StartEarly), together with what
// the device learns from it there (an arm: the joints it starts at). A device's start used to
// wait for the world's handshake and answer, and then load its models; now it takes the
// longer of the two.
//
// A world out of reach may be restarting (a tool's adapter is powered while it does): it is
// waited for, briefly, before the device gives up.
//
// The cell hands a device the world model's certificate (--world-certificate: the cell issued
// it): the link then opens its secure channel at once, without a discovery connection to ask
// the world for its endpoints first. A certificate the world no longer has, or a policy it no
// longer offers, sends the link back to asking.
//
// Threading: start() and take() on the component's main thread; `then` runs on the thread
// that connects.
#include <CLI/CLI.hpp>
#include <functional>
#include <future>
#include <memory>
#include <string>

#include "devices/world/world_link.hpp"
#include "ua/client/client.hpp"

namespace skillcell::apps {

/// Where the world model is: its endpoint URL and, when the cell gave it, the file of its
/// application certificate (DER).
struct WorldAddress {
    std::string url;
    std::string certificateFile;
    [[nodiscard]] bool empty() const { return url.empty(); }
};

/// --world-certificate FILE, for the commands that have --world.
void addWorldCertificateOption(CLI::App* cmd, WorldAddress& address);

class WorldConnection {
public:
    /// Applied to the link on the connecting thread, once it is open.
    using Then = std::function<void(devices::WorldLink&)>;

    /// To the world model at `address`, acting for the world's robot `robot` (empty: for none).
    WorldConnection(WorldAddress address, std::string robot, Then then = {});
    /// Waits for the connecting thread, whose link then closes (a start that failed before
    /// its component took it).
    ~WorldConnection();
    WorldConnection(const WorldConnection&) = delete;
    WorldConnection& operator=(const WorldConnection&) = delete;

    /// Begins connecting as the component: its certificate, the user of its --client-user.
    void start(const ua::ClientSecurity& security, const std::string& applicationUri);
    /// The link, or why there is none (logged); waits for the connection to be settled. Once:
    /// BadInvalidState after that, or before start().
    ua::Result<std::unique_ptr<devices::WorldLink>> take();

private:
    WorldAddress address_;
    std::string robot_;
    Then then_;
    std::future<ua::Result<std::unique_ptr<devices::WorldLink>>> link_;
};

}  // namespace skillcell::apps
