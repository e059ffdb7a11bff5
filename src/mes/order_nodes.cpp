#include "mes/order_nodes.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>

#include "ua/address_space/ns0_ids.hpp"

namespace skillcell::mes {
namespace {

ua::Argument argument(const char* name, std::uint32_t type, const char* text, bool array = false) {
    ua::Argument a;
    a.name = name;
    a.dataType = ua::NodeId(type);
    a.valueRank = array ? ua::value_rank::kOneDimension : ua::value_rank::kScalar;
    a.description = ua::LocalizedText{"", text};
    return a;
}

ua::StatusCode statusOf(const Error& e) {
    switch (e.kind) {
        case ErrorKind::BadInput:
            return ua::status::BadInvalidArgument;
        case ErrorKind::Refused:
            return ua::status::BadInvalidState;
        case ErrorKind::Unavailable:
            return ua::status::BadResourceUnavailable;
        default:
            return ua::status::BadInternalError;
    }
}

std::string seconds(std::int64_t ms) {
    std::array<char, 32> text{};
    std::snprintf(text.data(), text.size(), "%.3f s", static_cast<double>(ms) / 1000.0);
    return text.data();
}

// "2.1 finished Skills/PickAndPlace @ urn:... at +1.204 s for 3.310 s {chosen: why} [retry 1
// of 2 after: ...]: reason": one attempt at one step, for `orders show`.
std::string describe(const StepRecord& s, std::int64_t orderStartMs) {
    std::string out = std::to_string(s.index) + "." + std::to_string(s.attempt) + " " +
                      toString(s.state) + " " + shortName(s.skillTypeIri) + " " + s.skillNodeId +
                      " @ " + s.componentUri;
    if (s.startedMs != 0) out += " at +" + seconds(s.startedMs - orderStartMs);
    if (s.endedMs != 0 && s.startedMs != 0) out += " for " + seconds(s.endedMs - s.startedMs);
    if (!s.choice.empty()) out += " {chosen: " + s.choice + "}";
    if (!s.note.empty()) out += " [" + s.note + "]";
    if (!s.reason.empty()) out += ": " + s.reason;
    return out;
}

}  // namespace

ua::NodeId ordersObject() {
    return ua::NodeId(1, ua::String("Orders"));
}

ua::NodeId orderMethod(const char* name) {
    return ua::NodeId(1, ua::String(std::string("Orders/") + name));
}

ua::NodeId orderVariable(std::int64_t order, const char* name) {
    return ua::NodeId(1, ua::String("Orders/" + std::to_string(order) + "/" + name));
}

bool hasEnded(const std::string& state) {
    // "refused": stopped before any motion, as the MES's progress says.
    return state == toString(RunState::Completed) || state == toString(RunState::Stopped) ||
           state == toString(RunState::Cancelled) || state == "refused";
}

ua::Result<std::unique_ptr<OrderNodes>> OrderNodes::create(
    ua::AddressSpace& as, std::shared_ptr<ProcessExecutor> executor, Journal& journal) {
    auto nodes = std::make_unique<OrderNodes>(Token{}, as);
    if (auto r = as.addObject(ua::NodeId(ua::ns0::ObjectsFolder), ordersObject(), "Orders"); !r) {
        return r.status();
    }
    using ua::ns0::Boolean;
    using ua::ns0::Int32;
    using ua::ns0::Int64;
    using ua::ns0::String;
    auto submit = as.addMethod(
        ordersObject(), orderMethod("SubmitOrder"), "SubmitOrder",
        {argument("ProcessIri", String, "the process to run"),
         argument("Priority", Int32, "-100..100; higher first, then the older order")},
        {argument("OrderId", Int64, "the order"),
         argument("Resumed", Boolean, "a Stopped order of the process was resumed instead")},
        [executor](const ua::Caller&, const ua::NodeId&, std::span<const ua::Variant> in,
                   std::vector<ua::Variant>& out) -> ua::StatusCode {
            const auto* iri = ua::methodInput<ua::String>(in, 0);
            const auto* priority = ua::methodInput<std::int32_t>(in, 1);
            if (iri == nullptr || priority == nullptr || iri->empty() || *priority < -100 ||
                *priority > 100) {
                return ua::status::BadInvalidArgument;
            }
            auto submitted = executor->submit(*iri, *priority);
            if (!submitted) {
                spdlog::warn("mes: SubmitOrder {}: {}", std::string(*iri), submitted.error());
                return statusOf(submitted.failure());
            }
            out.emplace_back(submitted->order);
            out.emplace_back(submitted->resumed);
            return ua::status::Good;
        });
    if (!submit) return submit.status();
    auto cancel = as.addMethod(
        ordersObject(), orderMethod("CancelOrder"), "CancelOrder",
        {argument("OrderId", Int64,
                  "the order: its running skills are halted, and it is never "
                  "resumed")},
        {},
        [executor, &journal](const ua::Caller&, const ua::NodeId&, std::span<const ua::Variant> in,
                             std::vector<ua::Variant>&) -> ua::StatusCode {
            const auto* id = ua::methodInput<std::int64_t>(in, 0);
            if (id == nullptr) return ua::status::BadInvalidArgument;
            if (auto r = journal.run(*id); r && !*r) return ua::status::BadNotFound;
            if (auto s = executor->stop(*id, /*cancel=*/true); !s) {
                spdlog::warn("mes: CancelOrder {}: {}", *id, s.error());
                return s.failure().kind == ErrorKind::BadInput ? ua::status::BadInvalidState
                                                               : ua::status::BadInternalError;
            }
            return ua::status::Good;
        });
    if (!cancel) return cancel.status();
    auto list = as.addMethod(
        ordersObject(), orderMethod("ListOrders"), "ListOrders",
        {argument("Count", Int32, "how many of the latest orders (1..10000)")},
        {argument("OrderIds", Int64, "oldest first", true),
         argument("Processes", String, "their processes", true),
         argument("States", String, "queued, running, completed, stopped, cancelled", true),
         argument("Priorities", Int32, "their priorities", true),
         argument("Progress", String, "what each does now, or why it stopped", true)},
        [executor, &journal](const ua::Caller&, const ua::NodeId&, std::span<const ua::Variant> in,
                             std::vector<ua::Variant>& out) -> ua::StatusCode {
            const auto* count = ua::methodInput<std::int32_t>(in, 0);
            if (count == nullptr || *count < 1 || *count > 10'000) {
                return ua::status::BadInvalidArgument;
            }
            auto runs = journal.recentRuns(*count);
            if (!runs) {
                spdlog::error("mes: ListOrders: {}", runs.error());
                return ua::status::BadInternalError;
            }
            std::map<std::int64_t, std::string> now;
            for (const auto& p : executor->running()) now[p.run] = p.line();
            std::vector<std::int64_t> ids;
            std::vector<ua::String> processes;
            std::vector<ua::String> states;
            std::vector<std::int32_t> priorities;
            std::vector<ua::String> progress;
            for (const auto& r : *runs) {
                ids.push_back(r.id);
                processes.emplace_back(r.processIri);
                states.emplace_back(toString(r.state));
                priorities.push_back(r.priority);
                const auto it = now.find(r.id);
                progress.emplace_back(it != now.end() ? it->second : r.reason);
            }
            out.push_back(ua::Variant::array(std::move(ids)));
            out.push_back(ua::Variant::array(std::move(processes)));
            out.push_back(ua::Variant::array(std::move(states)));
            out.push_back(ua::Variant::array(std::move(priorities)));
            out.push_back(ua::Variant::array(std::move(progress)));
            return ua::status::Good;
        });
    if (!list) return list.status();
    (*list)->requiredRole = ua::Role::Observer;
    auto get = as.addMethod(
        ordersObject(), orderMethod("GetOrder"), "GetOrder", {argument("OrderId", Int64, "")},
        {argument("Process", String, "its process"), argument("State", String, "its state"),
         argument("Reason", String, "why it stopped, or what it does now"),
         argument("Steps", String,
                  "each attempt at each step: step.attempt, state, skill type, skill @ "
                  "component, start (from the order's), duration, {why this instance}, [why "
                  "this attempt], reason",
                  true)},
        [executor, &journal](const ua::Caller&, const ua::NodeId&, std::span<const ua::Variant> in,
                             std::vector<ua::Variant>& out) -> ua::StatusCode {
            const auto* id = ua::methodInput<std::int64_t>(in, 0);
            if (id == nullptr) return ua::status::BadInvalidArgument;
            auto r = journal.run(*id);
            if (!r) {
                spdlog::error("mes: GetOrder: {}", r.error());
                return ua::status::BadInternalError;
            }
            if (!*r) return ua::status::BadNotFound;
            std::string reason = (*r)->reason;
            for (const auto& p : executor->running()) {
                if (p.run == *id) reason = p.line();
            }
            std::vector<ua::String> steps;
            for (const auto& s : (*r)->steps) steps.emplace_back(describe(s, (*r)->startedMs));
            out.emplace_back(ua::String((*r)->processIri));
            out.emplace_back(ua::String(toString((*r)->state)));
            out.emplace_back(ua::String(reason));
            out.push_back(ua::Variant::array(std::move(steps)));
            return ua::status::Good;
        });
    if (!get) return get.status();
    (*get)->requiredRole = ua::Role::Observer;
    return nodes;
}

void OrderNodes::show(const Progress& p) {
    if (p.run == 0) return;
    const ua::NodeId object(1, ua::String("Orders/" + std::to_string(p.run)));
    if (as_.find(object) == nullptr) {
        const auto made = as_.addObject(ordersObject(), object, std::to_string(p.run));
        for (const char* name : {"State", "Progress"}) {
            if (made) {
                (void)as_.addVariable(object, orderVariable(p.run, name), name,
                                      ua::NodeId(ua::ns0::String), ua::Variant(ua::String()));
            }
        }
    }
    (void)as_.setValue(orderVariable(p.run, "State"), ua::Variant(ua::String(p.state)));
    (void)as_.setValue(orderVariable(p.run, "Progress"), ua::Variant(ua::String(p.line())));
    if (hasEnded(p.state) && std::find(ended_.begin(), ended_.end(), p.run) == ended_.end()) {
        ended_.push_back(p.run);
        while (ended_.size() > kMaxEnded) removeOldest();
    }
}

void OrderNodes::removeOldest() {
    const std::int64_t id = ended_.front();
    ended_.pop_front();
    for (const char* name : {"State", "Progress"}) (void)as_.removeNode(orderVariable(id, name));
    (void)as_.removeNode(ua::NodeId(1, ua::String("Orders/" + std::to_string(id))));
}

}  // namespace skillcell::mes
