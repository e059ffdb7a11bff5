#include "demo_nodes.hpp"

#include <chrono>

namespace skillcell::apps {

using namespace ua;

StatusCode addDemoNodes(AddressSpace& as, DemoEventSink fireEvent) {
    const std::uint16_t ns = as.registerNamespace(kDemoNamespaceUri);
    auto id = [ns](const char* name) { return NodeId(ns, String(name)); };
    const NodeId demo = id("Demo");

    if (auto r = as.addObject(NodeId(ns0::ObjectsFolder), demo, "Demo"); !r) return r.status();
    struct VariableSpec {
        const char* name;
        std::uint32_t dataType;
        Variant value;
        std::uint8_t access;
        std::int32_t rank;
    };
    const VariableSpec variables[] = {
        {"Demo.Double", ns0::Double, Variant(1.5), access_level::kReadWrite, value_rank::kScalar},
        {"Demo.Int32", ns0::Int32, Variant(std::int32_t{42}), access_level::kReadWrite,
         value_rank::kScalar},
        {"Demo.String", ns0::String, Variant(String("hello")), access_level::kReadWrite,
         value_rank::kScalar},
        {"Demo.Boolean", ns0::Boolean, Variant(true), access_level::kReadWrite,
         value_rank::kScalar},
        {"Demo.DoubleArray", ns0::Double, Variant::array(std::vector<double>{1, 2, 3}),
         access_level::kReadWrite, value_rank::kOneDimension},
        {"Demo.ReadOnly", ns0::UInt32, Variant(std::uint32_t{7}), access_level::kCurrentRead,
         value_rank::kScalar},
    };
    for (const auto& v : variables) {
        auto r =
            as.addVariable(demo, id(v.name), v.name, NodeId(v.dataType), v.value, v.access, v.rank);
        if (!r) return r.status();
    }

    // A variable whose value is computed when read: application code backs variables with
    // callbacks instead of pushing values.
    const auto start = std::chrono::steady_clock::now();
    if (auto r = as.addVariable(demo, id("Demo.Uptime"), "Demo.Uptime", NodeId(ns0::Double),
                                Variant(0.0));
        !r) {
        return r.status();
    }
    StatusCode s = as.setValueSource(id("Demo.Uptime"), [start] {
        DataValue dv;
        dv.value = Variant(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        dv.sourceTimestamp = DateTime::now();
        return dv;
    });
    if (s.isBad()) return s;

    Argument a{"a", NodeId(ns0::Double), value_rank::kScalar, {}, {"", "first addend"}};
    Argument b{"b", NodeId(ns0::Double), value_rank::kScalar, {}, {"", "second addend"}};
    Argument sum{"sum", NodeId(ns0::Double), value_rank::kScalar, {}, {"", "a + b"}};
    auto add = as.addMethod(demo, id("Demo.Add"), "Demo.Add", {a, b}, {sum},
                            [](const Caller&, const NodeId&, std::span<const Variant> in,
                               std::vector<Variant>& out) -> StatusCode {
                                // Types and count are validated by the Call service against
                                // InputArguments before this runs.
                                out.emplace_back(*in[0].get<double>() + *in[1].get<double>());
                                return status::Good;
                            });
    if (!add) return add.status();
    if (!fireEvent) return status::Good;

    if (Node* node = as.find(demo)) node->eventNotifier = 1;  // SubscribeToEvents
    Argument message{"message", NodeId(ns0::String), value_rank::kScalar, {}, {"", "event text"}};
    auto fire =
        as.addMethod(demo, id("Demo.FireEvent"), "Demo.FireEvent", {message}, {},
                     [fireEvent, demo](const Caller&, const NodeId&, std::span<const Variant> in,
                                       std::vector<Variant>&) -> StatusCode {
                         fireEvent(demo, *in[0].get<String>());
                         return status::Good;
                     });
    return fire ? status::Good : fire.status();
}

}  // namespace skillcell::apps
