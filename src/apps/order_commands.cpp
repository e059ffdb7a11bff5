// `skillcell run PROCESS`: submit an order to the MES and follow it; `skillcell orders`: list,
// show, cancel and follow orders. Both speak to the MES's Objects/Orders (mes/order_nodes.hpp)
// over OPC UA, as any client may.
#include <asio/experimental/as_tuple.hpp>
#include <asio/steady_timer.hpp>
#include <asio/use_awaitable.hpp>
#include <iomanip>
#include <iostream>
#include <memory>

#include "client_security_options.hpp"
#include "commands.hpp"
#include "mes/order_nodes.hpp"

namespace skillcell::apps {
namespace {

struct OrderClientOptions {
    std::string mesUrl = "opc.tcp://localhost:4851";
    ClientSecurityOptions security;
};

struct RunOptions {
    std::string processIri;
    int priority = 0;
    bool noWait = false;
    double timeoutSeconds = 3600;
};

struct OrdersOptions {
    int count = 20;
    std::int64_t order = 0;
    double timeoutSeconds = 3600;
};

void addOrderClientOptions(CLI::App* cmd, OrderClientOptions& o) {
    cmd->add_option("--mes", o.mesUrl, "the MES's endpoint")->capture_default_str();
    addClientSecurityOptions(cmd, o.security);
}

asio::awaitable<bool> connect(ua::Client& client, const OrderClientOptions& o, const char* name) {
    auto config = commandClientConfig(o.security, name);
    if (!config) co_return false;
    const std::string url = o.mesUrl;
    if (const auto s = co_await client.connect(url, std::move(*config)); s.isBad()) {
        std::cerr << "cannot connect to the MES at " << o.mesUrl << ": " << explainConnectFailure(s)
                  << "\n";
        co_return false;
    }
    co_return true;
}

/// Why a method call of Objects/Orders was refused, for people.
std::string refusal(ua::StatusCode s, std::int64_t order) {
    const std::string id = std::to_string(order);
    if (s == ua::status::BadNotFound) return "the MES has no order " + id;
    if (s == ua::status::BadInvalidState) return "order " + id + " has ended already";
    if (s == ua::status::BadUserAccessDenied) {
        return "refused: the user lacks the role (submitting and cancelling need Operator)";
    }
    if (s == ua::status::BadResourceUnavailable) {
        return "the MES stands by: another MES runs the orders of its journal";
    }
    if (s == ua::status::BadMethodInvalid || s == ua::status::BadNodeIdUnknown) {
        return "this server has no Objects/Orders: is it a skillcell MES?";
    }
    return std::string(ua::statusName(s));
}

template <class T>
std::vector<T> elements(const ua::Variant& v) {
    std::vector<T> out;
    for (const auto& e : v.elements()) {
        if (const auto* x = std::get_if<T>(&e)) out.push_back(*x);
    }
    return out;
}

struct OrderEnd {
    std::string state;
    std::string reason;
    std::vector<ua::String> steps;
};

asio::awaitable<ua::Result<OrderEnd>> getOrder(ua::Client& client, std::int64_t order) {
    std::vector<ua::Variant> in{ua::Variant(order)};  // named: GCC 12 and co_await temporaries
    auto out =
        co_await client.call(mes::ordersObject(), mes::orderMethod("GetOrder"), std::move(in));
    if (!out) co_return out.status();
    if (out->size() != 4) co_return ua::status::BadUnexpectedError;
    OrderEnd end;
    if (const auto* s = (*out)[1].get<ua::String>()) end.state = *s;
    if (const auto* r = (*out)[2].get<ua::String>()) end.reason = *r;
    end.steps = elements<ua::String>((*out)[3]);
    co_return end;
}

/// Follows `order` to its end: PROGRESS lines as it goes (from Orders/<id>/Progress), then
/// OUTCOME. 0 completed, 1 stopped or cancelled, 2 cannot follow it.
asio::awaitable<int> follow(ua::Client& client, std::int64_t order, double timeoutSeconds) {
    auto state = std::make_shared<std::string>();
    auto shown = std::make_shared<std::string>();
    auto timer = std::make_shared<asio::steady_timer>(
        co_await asio::this_coro::executor,
        std::chrono::steady_clock::now() +
            std::chrono::milliseconds(static_cast<long>(timeoutSeconds * 1000)));
    auto lost = std::make_shared<std::string>();  // why the MES can no longer be heard
    ua::Subscription::StatusCallback onStatus = [lost, timer](ua::StatusCode s) {
        // BadTimeout: a late keep-alive (Good follows); lost notifications: the subscription
        // goes on. Anything else bad ends the session.
        if (s.isGood() || s == ua::status::BadTimeout || s == ua::status::BadMessageNotAvailable) {
            return;
        }
        *lost = ua::statusName(s);
        timer->cancel();
    };
    ua::SubscriptionSettings settings(50, 600, 10);
    auto subscription = co_await client.createSubscription(settings, std::move(onStatus));
    if (!subscription) {
        std::cerr << "cannot follow order " << order << ": "
                  << ua::statusName(subscription.status()) << "\n";
        co_return 2;
    }
    // Named locals: GCC 12 destroys temporaries of a co_await expression twice.
    ua::Subscription::DataChangeCallback onProgress = [shown](const ua::DataValue& v) {
        const auto* line = v.value ? v.value->get<ua::String>() : nullptr;
        if (line == nullptr || line->empty() || *line == *shown) return;
        *shown = *line;
        std::cout << "PROGRESS " << *line << std::endl;
    };
    ua::Subscription::DataChangeCallback onState = [state, timer](const ua::DataValue& v) {
        const auto* s = v.value ? v.value->get<ua::String>() : nullptr;
        if (s == nullptr) return;
        *state = *s;
        if (mes::hasEnded(*state)) timer->cancel();
    };
    const ua::NodeId progressNode = mes::orderVariable(order, "Progress");
    const ua::NodeId stateNode = mes::orderVariable(order, "State");
    auto progressItem = co_await (*subscription)
                            ->monitorDataChange(progressNode, ua::AttributeId::Value, 0, 100,
                                                std::nullopt, std::move(onProgress));
    auto stateItem = co_await (*subscription)
                         ->monitorDataChange(stateNode, ua::AttributeId::Value, 0, 10, std::nullopt,
                                             std::move(onState));
    // Not followable (ended long ago in this MES, or never), or ended already: what the
    // journal says, below.
    if (progressItem && stateItem && !mes::hasEnded(*state)) {
        co_await timer->async_wait(asio::experimental::as_tuple(asio::use_awaitable));
        if (!lost->empty()) {
            std::cout << "OUTCOME Lost (the connection to the MES ended: " << *lost
                      << "; a restarted MES resumes the order: `skillcell orders wait " << order
                      << "`)" << std::endl;
            co_return 1;
        }
        (void)co_await (*subscription)->remove();
        if (!mes::hasEnded(*state)) {
            std::cout << "PROGRESS no end after " << timeoutSeconds << " s: cancelling order "
                      << order << std::endl;
            std::vector<ua::Variant> in{ua::Variant(order)};
            (void)co_await client.call(mes::ordersObject(), mes::orderMethod("CancelOrder"),
                                       std::move(in));
        }
    } else {
        (void)co_await (*subscription)->remove();
    }
    auto end = co_await getOrder(client, order);
    if (!end) {
        std::cerr << "cannot read order " << order << ": " << refusal(end.status(), order) << "\n";
        co_return 2;
    }
    if (end->state == "completed") {
        std::cout << "OUTCOME Finished" << std::endl;
        co_return 0;
    }
    std::cout << "OUTCOME " << (end->state == "cancelled" ? "Cancelled" : "Failed") << " ("
              << end->reason << ")" << std::endl;
    co_return 1;
}

asio::awaitable<int> runProcess(ua::Client& client, const OrderClientOptions& c,
                                const RunOptions& o) {
    if (!co_await connect(client, c, "skillcell run")) co_return 2;
    std::vector<ua::Variant> in{ua::Variant(ua::String(o.processIri)),
                                ua::Variant(std::int32_t{o.priority})};
    auto out =
        co_await client.call(mes::ordersObject(), mes::orderMethod("SubmitOrder"), std::move(in));
    if (!out || out->size() != 2 || (*out)[0].get<std::int64_t>() == nullptr) {
        std::cerr << "the MES refused the order: "
                  << refusal(out ? ua::StatusCode(ua::status::BadUnexpectedError) : out.status(), 0)
                  << "\n";
        (void)co_await client.disconnect();
        co_return 2;
    }
    const std::int64_t order = *(*out)[0].get<std::int64_t>();
    const auto* resumed = (*out)[1].get<bool>();
    std::cout << "ORDER " << order
              << (resumed != nullptr && *resumed ? " (the process's stopped order, resumed)" : "")
              << std::endl;
    int code = 0;
    if (!o.noWait) code = co_await follow(client, order, o.timeoutSeconds);
    (void)co_await client.disconnect();
    co_return code;
}

std::string shorten(const std::string& iri) {
    const auto cut = iri.find_last_of("#/");
    return cut == std::string::npos ? iri : iri.substr(cut + 1);
}

asio::awaitable<int> listOrders(ua::Client& client, const OrderClientOptions& c,
                                const OrdersOptions& o) {
    if (!co_await connect(client, c, "skillcell orders")) co_return 2;
    std::vector<ua::Variant> in{ua::Variant(std::int32_t{o.count})};
    auto out =
        co_await client.call(mes::ordersObject(), mes::orderMethod("ListOrders"), std::move(in));
    (void)co_await client.disconnect();
    if (!out || out->size() != 5) {
        std::cerr << "cannot list the orders: "
                  << refusal(out ? ua::StatusCode(ua::status::BadUnexpectedError) : out.status(), 0)
                  << "\n";
        co_return 2;
    }
    const auto ids = elements<std::int64_t>((*out)[0]);
    const auto processes = elements<ua::String>((*out)[1]);
    const auto states = elements<ua::String>((*out)[2]);
    const auto priorities = elements<std::int32_t>((*out)[3]);
    const auto progress = elements<ua::String>((*out)[4]);
    std::cout << std::left << std::setw(7) << "ORDER" << std::setw(11) << "STATE" << std::setw(5)
              << "PRIO" << std::setw(28) << "PROCESS"
              << "PROGRESS / REASON\n";
    for (std::size_t i = 0; i < ids.size() && i < processes.size() && i < states.size() &&
                            i < priorities.size() && i < progress.size();
         ++i) {
        std::cout << std::left << std::setw(7) << ids[i] << std::setw(11) << std::string(states[i])
                  << std::setw(5) << priorities[i] << std::setw(28) << shorten(processes[i])
                  << std::string(progress[i]) << "\n";
    }
    if (ids.empty()) std::cout << "(no orders)\n";
    co_return 0;
}

asio::awaitable<int> showOrder(ua::Client& client, const OrderClientOptions& c,
                               const OrdersOptions& o) {
    if (!co_await connect(client, c, "skillcell orders")) co_return 2;
    auto end = co_await getOrder(client, o.order);
    (void)co_await client.disconnect();
    if (!end) {
        std::cerr << refusal(end.status(), o.order) << "\n";
        co_return 2;
    }
    std::cout << "order " << o.order << ": " << end->state;
    if (!end->reason.empty()) std::cout << " - " << end->reason;
    std::cout << "\nsteps (step.attempt state type skill @ component, start, duration, "
                 "{why this instance}, [why this attempt]: reason):\n";
    for (const auto& s : end->steps) std::cout << "  " << std::string(s) << "\n";
    if (end->steps.empty()) std::cout << "  (none begun)\n";
    co_return 0;
}

asio::awaitable<int> cancelOrder(ua::Client& client, const OrderClientOptions& c,
                                 const OrdersOptions& o) {
    if (!co_await connect(client, c, "skillcell orders")) co_return 2;
    std::vector<ua::Variant> in{ua::Variant(o.order)};
    auto out =
        co_await client.call(mes::ordersObject(), mes::orderMethod("CancelOrder"), std::move(in));
    if (!out) {
        (void)co_await client.disconnect();
        std::cerr << "cannot cancel: " << refusal(out.status(), o.order) << "\n";
        co_return 1;
    }
    std::cout << "order " << o.order << " cancelled: its running skills are halted" << std::endl;
    (void)co_await client.disconnect();
    co_return 0;
}

asio::awaitable<int> waitOrder(ua::Client& client, const OrderClientOptions& c,
                               const OrdersOptions& o) {
    if (!co_await connect(client, c, "skillcell orders")) co_return 2;
    const int code = co_await follow(client, o.order, o.timeoutSeconds);
    (void)co_await client.disconnect();
    co_return code;
}

}  // namespace

Command addRunCommand(CLI::App& app) {
    auto c = std::make_shared<OrderClientOptions>();
    auto o = std::make_shared<RunOptions>();
    auto* cmd = app.add_subcommand(
        "run",
        "Submit an order of a process to the MES and follow it: ORDER <id>, then PROGRESS "
        "lines as steps start and end, then OUTCOME. Orders that need different components run "
        "at the same time. Submitting a process whose last order stopped resumes that order. "
        "Exit code 0 when it completed, 1 when it stopped or was cancelled (the reason is "
        "printed), 2 when the MES cannot be reached or refuses the order.");
    cmd->add_option("process", o->processIri,
                    "the process's IRI, e.g. http://skillcell.dev/demo#pickAndPlaceTwoBoxes")
        ->required();
    cmd->add_option("--priority", o->priority,
                    "-100..100: among orders waiting for a component, the higher goes first")
        ->check(CLI::Range(-100, 100))
        ->capture_default_str();
    cmd->add_flag("--no-wait", o->noWait, "print the order's id and return at once");
    cmd->add_option("--timeout", o->timeoutSeconds,
                    "seconds to wait for the end; then the order is cancelled")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    addOrderClientOptions(cmd, *c);
    return {cmd, [c, o] {
                return runClientCommand(
                    [c, o](ua::Client& client) { return runProcess(client, *c, *o); });
            }};
}

Command addOrdersCommand(CLI::App& app) {
    auto c = std::make_shared<OrderClientOptions>();
    auto o = std::make_shared<OrdersOptions>();
    auto* cmd = app.add_subcommand(
        "orders",
        "The MES's orders: with no subcommand, the latest (queued, running, completed, "
        "stopped, cancelled) with what each does now or why it stopped.");
    cmd->add_option("--count", o->count, "how many of the latest orders")
        ->check(CLI::Range(1, 10'000))
        ->capture_default_str();
    addOrderClientOptions(cmd, *c);
    auto* show = cmd->add_subcommand(
        "show",
        "One order: its state, and every attempt at every step with the skill chosen, "
        "when it ran, for how long, why the attempt was made and how it ended.");
    show->add_option("id", o->order, "the order")->required();
    auto* cancel = cmd->add_subcommand(
        "cancel",
        "Cancel an order: a queued one never starts; a running one's skills are "
        "halted, and it is never resumed. Exit code 1 when it has ended already.");
    cancel->add_option("id", o->order, "the order")->required();
    auto* wait = cmd->add_subcommand(
        "wait",
        "Follow an order to its end as `run` does (an order resumed by a restarted "
        "MES, one submitted with --no-wait).");
    wait->add_option("id", o->order, "the order")->required();
    wait->add_option("--timeout", o->timeoutSeconds,
                     "seconds to wait for the end; then the order is cancelled")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    for (auto* sub : {show, cancel, wait}) addOrderClientOptions(sub, *c);
    return {cmd, [c, o, show, cancel, wait] {
                return runClientCommand(
                    [c, o, show, cancel, wait](ua::Client& client) -> asio::awaitable<int> {
                        if (show->parsed()) return showOrder(client, *c, *o);
                        if (cancel->parsed()) return cancelOrder(client, *c, *o);
                        if (wait->parsed()) return waitOrder(client, *c, *o);
                        return listOrders(client, *c, *o);
                    });
            }};
}

}  // namespace skillcell::apps
