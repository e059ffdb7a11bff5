#pragma once
// The demo content of `skillcell server`: a Demo object with a few variables and a method,
// the same nodes the node-opcua interop peer (tests/interop/server.js) offers, so one set of
// interop scripts and benchmarks runs against either server.
#include <functional>

#include "ua/address_space/address_space.hpp"

namespace skillcell::apps {

inline constexpr std::string_view kDemoNamespaceUri = "urn:skillcell:demo";

/// Adds Objects/Demo with Demo.Double, Demo.Int32, Demo.String, Demo.Boolean,
/// Demo.DoubleArray (read/write), Demo.ReadOnly, Demo.Uptime (a value callback) and the
/// method Demo.Add(a, b) -> sum. Returns the first failure, if any.
/// With `fireEvent` (the server's event API, e.g. bound to Server::fireEvent), Demo is an
/// event notifier and gets the method Demo.FireEvent(message), which fires a BaseEventType
/// event from Demo with Severity 500.
using DemoEventSink = std::function<void(const ua::NodeId& source, ua::String message)>;
ua::StatusCode addDemoNodes(ua::AddressSpace& as, DemoEventSink fireEvent = {});

}  // namespace skillcell::apps
