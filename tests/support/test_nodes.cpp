#include "test_nodes.hpp"

namespace skillcell::test {

ua::StatusCode addDoublingMethod(ua::AddressSpace& as, const ua::NodeId& id) {
    using namespace ua;
    Argument in{"x", NodeId(11), value_rank::kScalar, {}, {}};
    Argument out{"y", NodeId(11), value_rank::kScalar, {}, {}};
    auto added = as.addMethod(NodeId(85), id, "Twice", {in}, {out},
                              [](const Caller&, const NodeId&, std::span<const Variant> inputs,
                                 std::vector<Variant>& outputs) {
                                  outputs.emplace_back(*inputs[0].get<double>() * 2);
                                  return StatusCode(status::Good);
                              });
    return added ? StatusCode(status::Good) : added.status();
}

}  // namespace skillcell::test
