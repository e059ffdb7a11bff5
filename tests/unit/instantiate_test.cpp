// instantiate(): ProgramStateMachineType (the skills' base type), a subtype with its own
// declarations overriding the supertype's, a 3D frame variable, and the error cases.
#include <gtest/gtest.h>

#include "ua/address_space/instantiate.hpp"
#include "ua/nodeset/embedded_models.hpp"

namespace instantiate_test {

using namespace skillcell::ua;

namespace {

AddressSpace baseSpace() {
    AddressSpace as("urn:test:server");
    const auto st = loadBaseNodeSet(as);
    EXPECT_TRUE(st.ok()) << st.error;
    return as;
}

const Node* childOf(const AddressSpace& as, const NodeId& parent, std::string_view path) {
    NodeId current = parent;
    const Node* n = as.find(current);
    while (!path.empty() && n != nullptr) {
        const auto slash = path.find('/');
        const auto name = path.substr(0, slash);
        n = as.findChild(current, QualifiedName{0, String(name)});
        if (n == nullptr) {
            // children of types in other namespaces
            for (std::uint16_t ns = 1; ns < 4 && n == nullptr; ++ns) {
                n = as.findChild(current, QualifiedName{ns, String(name)});
            }
        }
        if (n == nullptr) return nullptr;
        current = n->nodeId;
        path = slash == std::string_view::npos ? std::string_view{} : path.substr(slash + 1);
    }
    return n;
}

bool hasRef(const Node& n, std::uint32_t type, const NodeId& target, bool forward = true) {
    return std::find(n.references.begin(), n.references.end(),
                     Reference{NodeId(type), target, forward}) != n.references.end();
}

constexpr std::uint32_t kProgramStateMachineType = 2391;
constexpr std::uint32_t kFiniteStateVariableType = 2760;
constexpr std::uint32_t kFiniteTransitionVariableType = 2767;

}  // namespace

TEST(Instantiate, ProgramStateMachine) {
    AddressSpace as = baseSpace();
    const auto before = as.size();
    auto id = instantiate(as, NodeId(kProgramStateMachineType), NodeId(ns0::ObjectsFolder),
                          NodeId(ns0::Organizes), QualifiedName{1, "Skill"},
                          {NodeId(1, "Skill"), {"Start", "Halt", "Reset", "FinalResultData"}, {}});
    ASSERT_TRUE(id.ok()) << statusName(id.status());
    EXPECT_EQ(*id, NodeId(1, "Skill"));
    const Node* skill = as.find(*id);
    ASSERT_NE(skill, nullptr);
    EXPECT_EQ(skill->nodeClass, NodeClass::Object);
    EXPECT_EQ(as.typeDefinitionOf(*skill), NodeId(kProgramStateMachineType));
    EXPECT_TRUE(hasRef(*as.find(NodeId(ns0::ObjectsFolder)), ns0::Organizes, *id));

    // CurrentState: ProgramStateMachineType's declaration (with Number) overrides
    // FiniteStateMachineType's and StateMachineType's.
    const Node* current = childOf(as, *id, "CurrentState");
    ASSERT_NE(current, nullptr);
    EXPECT_EQ(current->nodeId, NodeId(1, "Skill/CurrentState"));
    EXPECT_EQ(current->dataType, NodeId(21));  // LocalizedText
    EXPECT_EQ(as.typeDefinitionOf(*current), NodeId(kFiniteStateVariableType));
    EXPECT_TRUE(hasRef(*skill, ns0::HasComponent, current->nodeId));
    ASSERT_NE(childOf(as, *id, "CurrentState/Id"), nullptr);
    EXPECT_EQ(childOf(as, *id, "CurrentState/Id")->dataType, NodeId(ns0::NodeIdType));
    EXPECT_EQ(as.typeDefinitionOf(*childOf(as, *id, "CurrentState/Id")), NodeId(ns0::PropertyType));
    ASSERT_NE(childOf(as, *id, "CurrentState/Number"), nullptr);
    // Optional children of the variable type are not created unless asked for.
    EXPECT_EQ(childOf(as, *id, "CurrentState/EffectiveDisplayName"), nullptr);

    const Node* last = childOf(as, *id, "LastTransition");
    ASSERT_NE(last, nullptr);
    EXPECT_EQ(as.typeDefinitionOf(*last), NodeId(kFiniteTransitionVariableType));
    EXPECT_NE(childOf(as, *id, "LastTransition/Id"), nullptr);
    EXPECT_NE(childOf(as, *id, "LastTransition/Number"), nullptr);
    EXPECT_NE(childOf(as, *id, "LastTransition/TransitionTime"), nullptr);

    // Mandatory properties; Creatable has no modelling rule (a property of the type).
    for (const char* p : {"Deletable", "AutoDelete", "RecycleCount"}) {
        EXPECT_NE(childOf(as, *id, p), nullptr) << p;
    }
    EXPECT_EQ(childOf(as, *id, "Creatable"), nullptr);
    // States and transitions belong to the type.
    EXPECT_EQ(childOf(as, *id, "Ready"), nullptr);
    EXPECT_EQ(childOf(as, *id, "HaltedToReady"), nullptr);
    // Asked-for methods and optional object; the others are not there.
    const Node* start = childOf(as, *id, "Start");
    ASSERT_NE(start, nullptr);
    EXPECT_EQ(start->nodeClass, NodeClass::Method);
    EXPECT_EQ(start->nodeId, NodeId(1, "Skill/Start"));
    EXPECT_NE(childOf(as, *id, "Halt"), nullptr);
    EXPECT_NE(childOf(as, *id, "Reset"), nullptr);
    EXPECT_EQ(childOf(as, *id, "Suspend"), nullptr);
    EXPECT_NE(childOf(as, *id, "FinalResultData"), nullptr);

    // No instance carries a modelling rule.
    std::size_t created = 0;
    as.forEachNode([&](const Node& n) {
        if (n.nodeId.namespaceIndex() != 1) return;
        ++created;
        for (const auto& r : n.references) {
            EXPECT_NE(r.referenceTypeId, NodeId(ns0::HasModellingRule)) << n.nodeId.toString();
        }
    });
    EXPECT_EQ(as.size(), before + created);

    // The type's state nodes keep their numbers (the values a skill copies into
    // CurrentState/Number).
    const Node* haltedNumber = childOf(as, NodeId(kProgramStateMachineType), "Halted/StateNumber");
    ASSERT_NE(haltedNumber, nullptr);
    EXPECT_EQ(*haltedNumber->value.value, Variant(std::uint32_t{11}));
}

TEST(Instantiate, SubtypeOverridesAndNestedDeclarations) {
    AddressSpace as = baseSpace();
    constexpr std::string_view kModel = R"(<?xml version="1.0"?>
<UANodeSet xmlns="http://opcfoundation.org/UA/2011/03/UANodeSet.xsd"
           xmlns:uax="http://opcfoundation.org/UA/2008/02/Types.xsd">
  <NamespaceUris><Uri>urn:test:skills</Uri></NamespaceUris>
  <UAObjectType NodeId="ns=1;i=1" BrowseName="1:MoveSkillType">
    <References>
      <Reference ReferenceType="i=45" IsForward="false">i=2391</Reference>
      <Reference ReferenceType="i=47">ns=1;i=2</Reference>
      <Reference ReferenceType="i=47">ns=1;i=10</Reference>
    </References>
  </UAObjectType>
  <UAObject NodeId="ns=1;i=2" BrowseName="1:ParameterSet">
    <References>
      <Reference ReferenceType="i=40">i=58</Reference>
      <Reference ReferenceType="i=37">i=78</Reference>
      <Reference ReferenceType="i=47">ns=1;i=3</Reference>
    </References>
  </UAObject>
  <UAVariable NodeId="ns=1;i=3" BrowseName="1:Target" DataType="i=18814" AccessLevel="3">
    <References>
      <Reference ReferenceType="i=40">i=18791</Reference>
      <Reference ReferenceType="i=37">i=78</Reference>
    </References>
  </UAVariable>
  <UAVariable NodeId="ns=1;i=10" BrowseName="CurrentState" DataType="i=21">
    <Description>Overridden by the subtype</Description>
    <References>
      <Reference ReferenceType="i=40">i=2760</Reference>
      <Reference ReferenceType="i=37">i=78</Reference>
    </References>
  </UAVariable>
</UANodeSet>)";
    auto st = loadNodeSet(as, kModel, "skills.xml");
    ASSERT_TRUE(st.ok()) << st.error;
    const NodeId type(2, 1u);
    // Without options.nodeId the id would be childNodeId(Objects) = "i=85/Move" in
    // namespace 0; applications give their own.
    auto id = instantiate(as, type, NodeId(ns0::ObjectsFolder), NodeId(ns0::Organizes),
                          QualifiedName{2, "Move"}, {NodeId(2, "Move"), {}, {}});
    ASSERT_TRUE(id.ok()) << statusName(id.status());
    EXPECT_EQ(*id, NodeId(2, "Move"));
    const Node* current = childOf(as, *id, "CurrentState");
    ASSERT_NE(current, nullptr);
    EXPECT_EQ(current->description.text, "Overridden by the subtype");
    // The override's own children: none, but the type's (FiniteStateVariableType) Id is
    // still mandatory.
    EXPECT_NE(childOf(as, *id, "CurrentState/Id"), nullptr);
    EXPECT_EQ(childOf(as, *id, "CurrentState/Number"), nullptr);
    // Children of children, through the variable type of the 3D frame.
    const Node* target = childOf(as, *id, "ParameterSet/Target");
    ASSERT_NE(target, nullptr);
    EXPECT_EQ(target->accessLevel, 3);
    EXPECT_EQ(target->dataType, NodeId(18814u));
    for (const char* p :
         {"CartesianCoordinates/X", "CartesianCoordinates/Y", "CartesianCoordinates/Z",
          "Orientation/A", "Orientation/B", "Orientation/C"}) {
        EXPECT_NE(childOf(as, target->nodeId, p), nullptr) << p;
    }
    EXPECT_EQ(childOf(as, target->nodeId, "CartesianCoordinates/X")->nodeId,
              NodeId(2, "Move/ParameterSet/Target/CartesianCoordinates/X"));

    // Again under the same name: every id is checked first, nothing is added.
    const auto size = as.size();
    auto again = instantiate(as, type, NodeId(ns0::ObjectsFolder), NodeId(ns0::Organizes),
                             QualifiedName{2, "Move"}, {NodeId(2, "Move"), {}, {}});
    EXPECT_EQ(again.status(), status::BadNodeIdExists);
    EXPECT_EQ(as.size(), size);
}

TEST(Instantiate, VariableTypeAndErrors) {
    AddressSpace as = baseSpace();
    auto frame = instantiate(as, NodeId(18791u), NodeId(ns0::ObjectsFolder), {},
                             QualifiedName{1, "Frame"}, {NodeId(1, "Frame"), {}, {}});
    ASSERT_TRUE(frame.ok());
    const Node* f = as.find(*frame);
    EXPECT_EQ(f->nodeClass, NodeClass::Variable);
    EXPECT_EQ(f->dataType, NodeId(18814u));
    EXPECT_NE(childOf(as, *frame, "Orientation/C"), nullptr);

    // Abstract type, unknown type, unknown parent, non-reference type.
    EXPECT_EQ(instantiate(as, NodeId(2771u), NodeId(ns0::ObjectsFolder), {}, QualifiedName{1, "X"})
                  .status(),
              status::BadTypeDefinitionInvalid);
    EXPECT_EQ(instantiate(as, NodeId(1, 99u), NodeId(ns0::ObjectsFolder), {}, QualifiedName{1, "X"})
                  .status(),
              status::BadTypeDefinitionInvalid);
    EXPECT_EQ(instantiate(as, NodeId(2391u), NodeId(1, "nope"), {}, QualifiedName{1, "X"}).status(),
              status::BadNodeIdUnknown);
    EXPECT_EQ(instantiate(as, NodeId(2391u), NodeId(ns0::ObjectsFolder), NodeId(ns0::Server),
                          QualifiedName{1, "X"})
                  .status(),
              status::BadReferenceTypeIdInvalid);
}

}  // namespace instantiate_test
