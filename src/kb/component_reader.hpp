#pragma once
// ComponentReader: what the knowledge base reads from a component when it records it (one
// session, a few requests): the server's NamespaceArray (which models the component uses)
// and the current Value of every parameter of the skills the detector found there.
//
// Enumeration values are read as their names: the EnumStrings property of the parameter's
// data type, asked of the component itself (a number when it has none). A 3DFrame is a pose.
//
// Bounded: every step has the ClientConfig's timeouts, and cancel() (from any thread) drops
// the connection of a read in progress, so that a component that hangs holds up neither the
// KB's discovery worker for long nor its shutdown.
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "kb/component_graph.hpp"
#include "ua/client/client.hpp"

namespace skillcell::ua {
class BlockingClient;
}

namespace skillcell::kb {

struct ComponentReading {
    std::vector<std::string> namespaceArray;  // the server's, index 0 first
    SkillParameterValues values;              // skills whose parameters were read
};

/// A parameter's value as the KB records it: a String or LocalizedText as text, a number
/// (not a Boolean) as a number, an Int32 of an enumeration as the name at its index in
/// `enumStrings` (the number when there is none), a 3DFrame as a pose. nullopt for anything
/// else (arrays, other structures, NaN) and for an empty value.
[[nodiscard]] std::optional<ParameterValue> parameterValue(
    const skills::SkillParameter& parameter, const ua::Variant& value,
    const std::vector<std::string>* enumStrings = nullptr);

class ComponentReader {
public:
    /// `config`: how to connect (security, identity, timeouts) to every component.
    explicit ComponentReader(ua::ClientConfig config) : config_(std::move(config)) {}

    /// Connects to `endpointUrl` and reads the NamespaceArray and the parameter values of
    /// `skills` (the component's, as the detector found them). Blocks, within the timeouts;
    /// call it from a thread that may wait. BadShutdown once cancelled.
    [[nodiscard]] ua::Result<ComponentReading> read(
        const std::string& endpointUrl, const std::vector<skills::SkillInstance>& skills);
    /// Ends a read in progress (it fails) and refuses every later one. Any thread.
    void cancel();

private:
    ua::Result<ComponentReading> readWith(ua::BlockingClient& client,
                                          const std::string& endpointUrl,
                                          const std::vector<skills::SkillInstance>& skills);
    [[nodiscard]] bool cancelled();

    ua::ClientConfig config_;
    std::mutex mutex_;
    ua::BlockingClient* current_ = nullptr;  // guarded by mutex_
    bool cancelled_ = false;                 // guarded by mutex_
};

}  // namespace skillcell::kb
