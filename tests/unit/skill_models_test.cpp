// The companion models under models/Skillcell.*.NodeSet2.xml: they load in dependency
// order and refuse to load without their RequiredModels; every skill type is a SkillType
// and a ProgramStateMachineType; every parameter has its data type, rank, modelling rule
// and engineering units; the frame and enumeration types decode through the registry; an
// instantiated skill has all its parameters; export -> reload reproduces every node.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "ua/address_space/instantiate.hpp"
#include "ua/nodeset/companion_models.hpp"
#include "ua/nodeset/embedded_models.hpp"
#include "ua/nodeset/nodeset_exporter.hpp"
#include "ua/nodeset/nodeset_loader.hpp"

namespace skill_models_test {

using namespace skillcell::ua;
namespace cm = skillcell::ua::companion;

namespace {

constexpr std::string_view kUnece = "http://www.opcfoundation.org/UA/units/un/cefact";
constexpr std::int32_t kMetre = 0x4D5452;            // MTR
constexpr std::int32_t kKilogram = 0x4B474D;         // KGM
constexpr std::int32_t kMetrePerSecond = 0x4D5453;   // MTS
constexpr std::int32_t kMetrePerSecond2 = 0x4D534B;  // MSK
constexpr std::int32_t kRadian = 0x433831;           // C81
constexpr std::int32_t kRadianPerSecond = 0x3241;    // 2A
constexpr std::int32_t kRadianPerSecond2 = 0x3242;   // 2B
constexpr std::int32_t kNewton = 0x4E4557;           // NEW

AddressSpace baseSpace() {
    AddressSpace as("urn:test:server");
    const auto st = loadBaseNodeSet(as);
    EXPECT_TRUE(st.ok()) << st.error;
    return as;
}

AddressSpace fullSpace() {
    AddressSpace as = baseSpace();
    const auto st = loadCompanionModels(as);
    EXPECT_TRUE(st.ok()) << st.error;
    return as;
}

NodeId typeId(const AddressSpace& as, std::string_view uri, std::string_view name) {
    const auto id = findTypeByName(as, uri, name);
    EXPECT_TRUE(id.has_value()) << name;
    return id.value_or(NodeId());
}

QualifiedName diName(const AddressSpace& as, std::string_view name) {
    return QualifiedName{*as.namespaceIndex(cm::kDiUri), std::string(name)};
}

/// The decoded structure held by a variable (an ExtensionObject value).
DynamicStructure structureValue(const AddressSpace& as, const Node* variable) {
    EXPECT_NE(variable, nullptr);
    if (variable == nullptr || !variable->value.value) return {};
    const auto* eo = variable->value.value->get<ExtensionObject>();
    EXPECT_NE(eo, nullptr) << variable->nodeId.toString();
    if (eo == nullptr) return {};
    auto decoded = fromExtensionObject(as.dataTypes(), *eo);
    EXPECT_TRUE(decoded.ok()) << variable->nodeId.toString();
    return decoded.ok() ? *decoded : DynamicStructure{};
}

/// The UNECE unit id of an EUInformation property.
std::int32_t unitOf(const AddressSpace& as, const Node* property) {
    const DynamicStructure eu = structureValue(as, property);
    EXPECT_EQ(eu.dataTypeId, NodeId(ns0::EUInformation));
    const Variant* uri = eu.get("NamespaceUri");
    EXPECT_TRUE(uri != nullptr && *uri == Variant(String(kUnece)));
    const Variant* id = eu.get("UnitId");
    return id != nullptr && id->get<std::int32_t>() != nullptr ? *id->get<std::int32_t>() : 0;
}

enum class Kind { Frame, Double, DoubleArray, RangeArray, String, GripPointType };

struct Expected {
    std::string_view uri;
    std::string_view skillType;
    std::string_view parameter;
    Kind kind;
    std::int32_t unit = 0;  // Double, DoubleArray, RangeArray
    bool writable = true;
};

/// Every parameter of every concrete skill type (ARCHITECTURE.md, "The skill model"),
/// inherited ones included.
std::vector<Expected> expectedParameters() {
    std::vector<Expected> out;
    const auto add = [&](std::string_view uri, std::string_view type,
                         std::vector<Expected> params) {
        for (auto p : params) {
            p.uri = uri;
            p.skillType = type;
            out.push_back(p);
        }
    };
    // Every move: its tool frame, and where its manipulator reaches (read-only).
    const std::vector<Expected> move = {{{}, {}, "ToolFrame", Kind::Frame},
                                        {{}, {}, "Reach", Kind::Double, kMetre, false},
                                        {{}, {}, "ReachCentre", Kind::Frame, 0, false}};
    const std::vector<Expected> linear = {
        move[0],
        move[1],
        move[2],
        {{}, {}, "MaxVelocity", Kind::Double, kMetrePerSecond},
        {{}, {}, "MaxAcceleration", Kind::Double, kMetrePerSecond2}};
    const std::vector<Expected> ptp = {
        move[0],
        move[1],
        move[2],
        {{}, {}, "MaxVelocity", Kind::Double, kRadianPerSecond},
        {{}, {}, "MaxAcceleration", Kind::Double, kRadianPerSecond2}};
    const std::vector<Expected> cartesian = {{{}, {}, "TargetPosition", Kind::Frame},
                                             {{}, {}, "AxisBounds", Kind::RangeArray, kRadian}};
    const std::vector<Expected> joint = {
        {{}, {}, "TargetJointPosition", Kind::DoubleArray, kRadian}};
    const auto join = [](std::vector<Expected> a, const std::vector<Expected>& b) {
        a.insert(a.end(), b.begin(), b.end());
        return a;
    };
    add(cm::kRoboticSkillsUri, "MoveSkillType", move);
    add(cm::kRoboticSkillsUri, "LinearMoveSkillType", linear);
    add(cm::kRoboticSkillsUri, "PtpMoveSkillType", ptp);
    add(cm::kRoboticSkillsUri, "CartesianLinearMoveSkillType", join(linear, cartesian));
    add(cm::kRoboticSkillsUri, "CartesianPtpMoveSkillType", join(ptp, cartesian));
    add(cm::kRoboticSkillsUri, "JointLinearMoveSkillType", join(linear, joint));
    add(cm::kRoboticSkillsUri, "JointPtpMoveSkillType", join(ptp, joint));

    const std::vector<Expected> grip = {{{}, {}, "GripPointOffset", Kind::Frame, 0, false},
                                        {{}, {}, "GripPointType", Kind::GripPointType, 0, false},
                                        {{}, {}, "MaxPayload", Kind::Double, kKilogram, false},
                                        {{}, {}, "MaxGripWidth", Kind::Double, kMetre, false},
                                        {{}, {}, "RobotUri", Kind::String, 0, false}};
    add(cm::kGripperSkillsUri, "GripperSkillType", grip);
    add(cm::kGripperSkillsUri, "GraspGripperSkillType", grip);
    add(cm::kGripperSkillsUri, "ReleaseGripperSkillType", grip);
    add(cm::kGripperSkillsUri, "MoveGripperSkillType",
        join(grip,
             {{{}, {}, "Width", Kind::Double, kMetre}, {{}, {}, "Force", Kind::Double, kNewton}}));

    const std::vector<Expected> tool = {
        {{}, {}, "ToolPosition", Kind::Frame},
        {{}, {}, "MoveSkillControllerEndpoint", Kind::String, 0, false},
        {{}, {}, "RobotUri", Kind::String, 0, false}};
    const std::vector<Expected> app = {{{}, {}, "ToolAppUri", Kind::String}};
    add(cm::kToolChangerSkillsUri, "ToolChangerSkillType", tool);
    add(cm::kToolChangerSkillsUri, "AttachToolSkillType", join(tool, app));
    add(cm::kToolChangerSkillsUri, "DetachToolSkillType", tool);
    add(cm::kToolChangerSkillsUri, "ChangeToolSkillType", join(tool, app));

    add(cm::kCompositeSkillsUri, "PickAndPlaceSkillType",
        {{{}, {}, "ObjectId", Kind::String},
         {{}, {}, "ToolSkillControllerEndpoint", Kind::String},
         {{}, {}, "MoveSkillControllerEndpoint", Kind::String},
         {{}, {}, "PlacePosition", Kind::Frame}});
    add(cm::kMesSkillsUri, "ExecuteProcessSkillType", {{{}, {}, "ProcessIri", Kind::String}});
    return out;
}

InstantiateOptions named(std::string_view id) {
    InstantiateOptions o;
    o.nodeId = NodeId(1, std::string(id));
    return o;
}

std::size_t countChildren(const AddressSpace& as, const NodeId& parent) {
    const Node* n = as.find(parent);
    if (n == nullptr) return 0;
    return static_cast<std::size_t>(
        std::count_if(n->references.begin(), n->references.end(), [](const Reference& r) {
            return r.isForward && (r.referenceTypeId == NodeId(ns0::HasComponent) ||
                                   r.referenceTypeId == NodeId(ns0::HasProperty));
        }));
}

}  // namespace

TEST(SkillModels, EmbeddedAndLoadedInDependencyOrder) {
    for (const auto& m : kCompanionModels) {
        EXPECT_FALSE(embeddedModel(m.fileName).empty()) << m.fileName;
    }
    AddressSpace as = baseSpace();
    const auto before = as.size();
    const auto st = loadCompanionModels(as);
    ASSERT_TRUE(st.ok()) << st.error;
    EXPECT_EQ(as.size(), before + st.nodes);
    for (const auto& m : kCompanionModels) {
        const auto* model = as.findModel(m.uri);
        ASSERT_NE(model, nullptr) << m.uri;
        // The OPC Foundation's as published; ours at 1.00.0.
        if (m.uri == cm::kDiUri) {
            EXPECT_EQ(model->version, "1.05.0");
        } else if (m.uri == cm::kIaUri) {
            EXPECT_EQ(model->version, "1.01.4");
        } else if (m.uri == cm::kRoboticsUri) {
            EXPECT_EQ(model->version, "1.02");
        } else {
            EXPECT_EQ(model->version, "1.00.0");
        }
    }
    // Loading again adds nothing.
    const auto again = loadCompanionModels(as);
    EXPECT_TRUE(again.ok()) << again.error;
    EXPECT_EQ(again.nodes, 0u);
}

TEST(SkillModels, MissingRequiredModelsAreRefused) {
    // Each skill specification needs DI and Skills; Skills, IA and Robotics need DI; DI
    // needs namespace 0.
    {
        AddressSpace empty("urn:test:server");
        const auto st =
            loadNodeSet(empty, embeddedModel("Opc.Ua.Di.NodeSet2.xml"), "Opc.Ua.Di.NodeSet2.xml");
        EXPECT_NE(st.error.find("requires model http://opcfoundation.org/UA/"), std::string::npos)
            << st.error;
    }
    for (const auto& m : kCompanionModels) {
        if (m.uri == cm::kDiUri) continue;
        AddressSpace as = baseSpace();
        const auto before = as.size();
        const auto st = loadNodeSet(as, embeddedModel(m.fileName), m.fileName);
        ASSERT_FALSE(st.ok()) << m.fileName;
        EXPECT_EQ(st.error.rfind(std::string(m.fileName) + ":", 0), 0u) << st.error;
        EXPECT_NE(st.error.find("requires model http://opcfoundation.org/UA/DI/ version "),
                  std::string::npos)
            << st.error;
        EXPECT_NE(st.error.find(" or later, loaded: none"), std::string::npos) << st.error;
        EXPECT_EQ(as.size(), before) << "a refused model must add nothing";
    }
    // With DI but without Skills, a skill specification names Skills.
    AddressSpace as = baseSpace();
    ASSERT_TRUE(loadNodeSet(as, embeddedModel("Opc.Ua.Di.NodeSet2.xml"), "di").ok());
    const auto st = loadNodeSet(as, embeddedModel("Skillcell.GripperSkills.NodeSet2.xml"),
                                "Skillcell.GripperSkills.NodeSet2.xml");
    EXPECT_NE(st.error.find("requires model http://skillcell.dev/UA/Skills/"), std::string::npos)
        << st.error;
}

TEST(SkillModels, AComponentLoadsTheModelsItsSkillsNeedAndWhatTheyRequireInOrder) {
    const auto uris = [](const std::vector<CompanionModel>& models) {
        std::vector<std::string_view> out;
        for (const auto& m : models) out.push_back(m.uri);
        return out;
    };
    // A gripper adapter: its skill model requires Skills and DI (from the files'
    // <RequiredModel>s), not IA, Robotics or the other skill models.
    const std::vector<std::string_view> gripper{cm::kGripperSkillsUri};
    const auto forGripper = companionModelsFor(gripper);
    ASSERT_TRUE(forGripper.has_value());
    EXPECT_EQ(uris(*forGripper),
              (std::vector<std::string_view>{cm::kDiUri, cm::kSkillsUri, cm::kGripperSkillsUri}));
    // A robot: Robotics brings IA; each model after the ones it requires, once.
    const std::vector<std::string_view> robot{cm::kRoboticSkillsUri, cm::kRoboticsUri,
                                              cm::kSkillsUri};
    const auto forRobot = companionModelsFor(robot);
    ASSERT_TRUE(forRobot.has_value());
    EXPECT_EQ(uris(*forRobot),
              (std::vector<std::string_view>{cm::kDiUri, cm::kIaUri, cm::kRoboticsUri,
                                             cm::kSkillsUri, cm::kRoboticSkillsUri}));

    AddressSpace as = baseSpace();
    const auto before = as.size();
    const auto st = loadCompanionModels(as, gripper);
    ASSERT_TRUE(st.ok()) << st.error;
    EXPECT_EQ(as.size(), before + st.nodes);
    EXPECT_NE(as.findModel(cm::kGripperSkillsUri), nullptr);
    EXPECT_NE(as.findModel(cm::kSkillsUri), nullptr);
    EXPECT_EQ(as.findModel(cm::kRoboticsUri), nullptr);
    EXPECT_FALSE(as.namespaceIndex(cm::kRoboticSkillsUri).has_value());
    EXPECT_TRUE(findTypeByName(as, cm::kGripperSkillsUri, "GraspGripperSkillType").has_value());
    // Then the robot's: only what is missing is loaded, and it loads.
    const auto more = loadCompanionModels(as, robot);
    ASSERT_TRUE(more.ok()) << more.error;
    EXPECT_NE(as.findModel(cm::kRoboticsUri), nullptr);
    EXPECT_TRUE(findTypeByName(as, cm::kRoboticSkillsUri, "CartesianLinearMoveSkillType"));

    // Which model a type comes from, for a command line that names the type.
    EXPECT_EQ(companionModelDeclaring("GraspGripperSkillType"), cm::kGripperSkillsUri);
    EXPECT_EQ(companionModelDeclaring("CartesianLinearMoveSkillType"), cm::kRoboticSkillsUri);
    EXPECT_EQ(companionModelDeclaring("ExecuteProcessSkillType"), cm::kMesSkillsUri);
    EXPECT_EQ(companionModelDeclaring("MotionDeviceSystemType"), cm::kRoboticsUri);
    EXPECT_EQ(companionModelDeclaring("NoSuchSkillType"), std::nullopt);

    // An URI of no companion model: named, and nothing loaded.
    AddressSpace other = baseSpace();
    const auto size = other.size();
    const std::vector<std::string_view> unknown{cm::kGripperSkillsUri, "http://example.com/UA/X/"};
    std::string named;
    EXPECT_FALSE(companionModelsFor(unknown, &named).has_value());
    EXPECT_EQ(named, "http://example.com/UA/X/");
    const auto refused = loadCompanionModels(other, unknown);
    EXPECT_EQ(refused.error, "no companion model has the namespace URI http://example.com/UA/X/");
    EXPECT_EQ(other.size(), size);
}

TEST(SkillModels, SkillTypesAreProgramStateMachines) {
    const AddressSpace as = fullSpace();
    const NodeId skillType = *skillsNodeId(as, cm::kSkillType);
    const Node* skill = as.find(skillType);
    ASSERT_NE(skill, nullptr);
    EXPECT_EQ(skill->browseName.name, "SkillType");
    EXPECT_TRUE(skill->isAbstract);
    EXPECT_TRUE(as.isSubtypeOf(skillType, NodeId(ns0::ProgramStateMachineType)));
    const NodeId event = *skillsNodeId(as, cm::kSkillTransitionEventType);
    EXPECT_EQ(as.find(event)->browseName.name, "SkillTransitionEventType");
    EXPECT_TRUE(as.isSubtypeOf(event, NodeId(ns0::ProgramTransitionEventType)));
    EXPECT_NE(std::find(skill->references.begin(), skill->references.end(),
                        Reference{NodeId(ns0::GeneratesEvent), event, true}),
              skill->references.end());
    const Node* params = as.findChild(skillType, diName(as, "ParameterSet"));
    ASSERT_NE(params, nullptr);
    EXPECT_EQ(modellingRuleOf(*params), NodeId(ns0::ModellingRuleMandatory));

    // Every ObjectType of a skill specification is a skill, and every one ARCHITECTURE.md
    // names is there.
    std::vector<std::string> found;
    for (const auto& m : kCompanionModels) {
        if (m.uri == cm::kDiUri || m.uri == cm::kIaUri || m.uri == cm::kRoboticsUri ||
            m.uri == cm::kSkillsUri) {
            continue;
        }
        const auto ns = *as.namespaceIndex(m.uri);
        as.forEachNode([&](const Node& n) {
            if (n.nodeClass != NodeClass::ObjectType || n.nodeId.namespaceIndex() != ns) return;
            found.push_back(n.browseName.name);
            EXPECT_TRUE(as.isSubtypeOf(n.nodeId, skillType)) << n.browseName.name;
            EXPECT_TRUE(as.isSubtypeOf(n.nodeId, NodeId(ns0::ProgramStateMachineType)))
                << n.browseName.name;
        });
    }
    for (const auto& e : expectedParameters()) {
        EXPECT_NE(std::find(found.begin(), found.end(), e.skillType), found.end()) << e.skillType;
    }
    // The layering of figure 4: specific types below generic ones.
    const auto rs = [&](std::string_view n) { return typeId(as, cm::kRoboticSkillsUri, n); };
    EXPECT_TRUE(as.isSubtypeOf(rs("CartesianLinearMoveSkillType"), rs("LinearMoveSkillType")));
    EXPECT_TRUE(as.isSubtypeOf(rs("JointPtpMoveSkillType"), rs("PtpMoveSkillType")));
    EXPECT_TRUE(as.isSubtypeOf(rs("PtpMoveSkillType"), rs("MoveSkillType")));
    EXPECT_FALSE(as.isSubtypeOf(rs("CartesianPtpMoveSkillType"), rs("LinearMoveSkillType")));
    EXPECT_TRUE(as.find(rs("MoveSkillType"))->isAbstract);
    EXPECT_FALSE(as.find(rs("CartesianLinearMoveSkillType"))->isAbstract);
    EXPECT_TRUE(as.isSubtypeOf(typeId(as, cm::kGripperSkillsUri, "GraspGripperSkillType"),
                               typeId(as, cm::kGripperSkillsUri, "GripperSkillType")));
    EXPECT_TRUE(as.isSubtypeOf(typeId(as, cm::kRoboticsUri, "MotionDeviceSystemType"),
                               typeId(as, cm::kDiUri, "ComponentType")));
}

TEST(SkillModels, ParametersHaveDataTypesRulesAndUnits) {
    const AddressSpace as = fullSpace();
    const NodeId gripPointType = typeId(as, cm::kGripperSkillsUri, "GripPointTypeEnumeration");
    const std::vector<Expected> all = expectedParameters();
    std::string lastType;
    for (const auto& e : all) {
        const std::string what = std::string(e.skillType) + "/" + std::string(e.parameter);
        const NodeId type = typeId(as, e.uri, e.skillType);
        const Node* set = as.findChild(type, diName(as, "ParameterSet"));
        ASSERT_NE(set, nullptr) << what;
        const auto ns = *as.namespaceIndex(e.uri);
        const Node* p = as.findChild(set->nodeId, QualifiedName{ns, std::string(e.parameter)});
        ASSERT_NE(p, nullptr) << what;
        EXPECT_EQ(modellingRuleOf(*p), NodeId(ns0::ModellingRuleMandatory)) << what;
        EXPECT_EQ(p->accessLevel, e.writable ? 3 : 1) << what;
        switch (e.kind) {
            case Kind::Frame: {
                EXPECT_EQ(p->dataType, NodeId(ns0::ThreeDFrame)) << what;
                EXPECT_EQ(p->valueRank, -1) << what;
                EXPECT_EQ(as.typeDefinitionOf(*p), NodeId(ns0::ThreeDFrameType)) << what;
                const Node* xyz = as.findChild(p->nodeId, {0, "CartesianCoordinates"});
                const Node* abc = as.findChild(p->nodeId, {0, "Orientation"});
                ASSERT_TRUE(xyz != nullptr && abc != nullptr) << what;
                EXPECT_EQ(unitOf(as, as.findChild(xyz->nodeId, {0, "LengthUnit"})), kMetre) << what;
                EXPECT_EQ(unitOf(as, as.findChild(abc->nodeId, {0, "AngleUnit"})), kRadian) << what;
                const DynamicStructure frame = structureValue(as, p);
                EXPECT_EQ(frame.dataTypeId, NodeId(ns0::ThreeDFrame)) << what;
                break;
            }
            case Kind::Double:
            case Kind::DoubleArray:
            case Kind::RangeArray: {
                const bool range = e.kind == Kind::RangeArray;
                EXPECT_EQ(p->dataType, NodeId(range ? ns0::Range : ns0::Double)) << what;
                EXPECT_EQ(p->valueRank, e.kind == Kind::Double ? -1 : 1) << what;
                if (e.kind != Kind::Double) {
                    EXPECT_EQ(p->arrayDimensions, std::vector<std::uint32_t>{0}) << what;
                }
                // Range is no Number: AxisBounds is a data variable with units.
                EXPECT_EQ(as.typeDefinitionOf(*p),
                          NodeId(range ? ns0::BaseDataVariableType : ns0::BaseAnalogType))
                    << what;
                const Node* eu = as.findChild(p->nodeId, {0, "EngineeringUnits"});
                ASSERT_NE(eu, nullptr) << what;
                EXPECT_EQ(modellingRuleOf(*eu), NodeId(ns0::ModellingRuleMandatory)) << what;
                EXPECT_EQ(unitOf(as, eu), e.unit) << what;
                if (e.kind == Kind::Double) {
                    // A scalar has a default range; an instance narrows it to its device.
                    const Node* r = as.findChild(p->nodeId, {0, "EURange"});
                    ASSERT_NE(r, nullptr) << what;
                    EXPECT_EQ(modellingRuleOf(*r), NodeId(ns0::ModellingRuleOptional)) << what;
                    const DynamicStructure rv = structureValue(as, r);
                    EXPECT_EQ(*rv.get("Low"), Variant(0.0)) << what;
                    EXPECT_GT(*rv.get("High")->get<double>(), 0.0) << what;
                }
                break;
            }
            case Kind::String:
                EXPECT_EQ(p->dataType, NodeId(ns0::String)) << what;
                EXPECT_EQ(p->valueRank, -1) << what;
                break;
            case Kind::GripPointType:
                EXPECT_EQ(p->dataType, gripPointType) << what;
                EXPECT_TRUE(as.valueMatches(*p->value.value, p->dataType, p->valueRank)) << what;
                break;
        }
        // Nothing undeclared in the ParameterSet.
        if (lastType != e.skillType) {
            lastType = e.skillType;
            const auto expected = std::count_if(all.begin(), all.end(), [&](const Expected& x) {
                return x.skillType == e.skillType;
            });
            EXPECT_EQ(countChildren(as, set->nodeId), static_cast<std::size_t>(expected))
                << e.skillType;
        }
    }
}

TEST(SkillModels, FrameAndGripPointTypeDecodeThroughTheRegistry) {
    const AddressSpace as = fullSpace();
    const DataTypeRegistry& types = as.dataTypes();

    // The grip point type: an enumeration PARALLEL(0), VACUUM(1), MULTIFINGER(2).
    const NodeId gripPointType = typeId(as, cm::kGripperSkillsUri, "GripPointTypeEnumeration");
    EXPECT_TRUE(as.isSubtypeOf(gripPointType, NodeId(ns0::Enumeration)));
    const DataTypeInfo* info = types.find(gripPointType);
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(types.builtinTypeOf(gripPointType), BuiltinType::Int32);
    const auto* def = std::get_if<EnumDefinition>(&info->definition);
    ASSERT_NE(def, nullptr);
    ASSERT_EQ(def->fields.size(), 3u);
    const char* names[] = {"PARALLEL", "VACUUM", "MULTIFINGER"};
    for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_EQ(def->fields[i].name, names[i]);
        EXPECT_EQ(def->fields[i].value, static_cast<std::int64_t>(i));
    }
    const Node* strings = as.findChild(gripPointType, {0, "EnumStrings"});
    ASSERT_NE(strings, nullptr);
    EXPECT_EQ(*strings->value.value, Variant::array(std::vector<LocalizedText>{
                                         {"", "PARALLEL"}, {"", "VACUUM"}, {"", "MULTIFINGER"}}));
    EXPECT_EQ(as.find(gripPointType)->definition, info->definition);

    // The 3D frame: position (metres) and orientation (radians) as nested structures.
    const DataTypeInfo* frameInfo = types.find(NodeId(ns0::ThreeDFrame));
    ASSERT_NE(frameInfo, nullptr);
    auto frame = defaultStructure(types, NodeId(ns0::ThreeDFrame));
    ASSERT_TRUE(frame.ok());
    auto xyz = defaultStructure(types, NodeId(ns0::ThreeDCartesianCoordinates));
    auto abc = defaultStructure(types, NodeId(ns0::ThreeDOrientation));
    ASSERT_TRUE(xyz.ok() && abc.ok());
    xyz->set("X", Variant(0.5));
    xyz->set("Z", Variant(-0.25));
    abc->set("C", Variant(3.14159));
    ASSERT_TRUE(frame->set("CartesianCoordinates", Variant(*toExtensionObject(types, *xyz))));
    ASSERT_TRUE(frame->set("Orientation", Variant(*toExtensionObject(types, *abc))));
    const auto eo = toExtensionObject(types, *frame);
    ASSERT_TRUE(eo.ok());
    EXPECT_EQ(eo->typeId, frameInfo->binaryEncodingId);
    const auto back = fromExtensionObject(types, *eo);
    ASSERT_TRUE(back.ok());
    EXPECT_EQ(*back, *frame);
    // A frame parameter accepts such a value.
    const NodeId pick = typeId(as, cm::kCompositeSkillsUri, "PickAndPlaceSkillType");
    const Node* set = as.findChild(pick, diName(as, "ParameterSet"));
    const Node* place =
        as.findChild(set->nodeId, {*as.namespaceIndex(cm::kCompositeSkillsUri), "PlacePosition"});
    ASSERT_NE(place, nullptr);
    EXPECT_TRUE(as.valueMatches(Variant(*eo), place->dataType, place->valueRank));
}

TEST(SkillModels, InstantiatedSkillHasEveryParameter) {
    AddressSpace as = fullSpace();
    const NodeId type = typeId(as, cm::kRoboticSkillsUri, "CartesianLinearMoveSkillType");
    auto id = instantiate(as, type, NodeId(ns0::ObjectsFolder), NodeId(ns0::Organizes),
                          QualifiedName{1, "Move"}, named("Move"));
    ASSERT_TRUE(id.ok()) << statusName(id.status());
    const Node* set = as.findChild(*id, diName(as, "ParameterSet"));
    ASSERT_NE(set, nullptr);
    const auto ns = *as.namespaceIndex(cm::kRoboticSkillsUri);
    for (const char* name :
         {"ToolFrame", "MaxVelocity", "MaxAcceleration", "TargetPosition", "AxisBounds"}) {
        const Node* p = as.findChild(set->nodeId, QualifiedName{ns, name});
        ASSERT_NE(p, nullptr) << name;
        EXPECT_EQ(modellingRuleOf(*p), NodeId()) << "instances have no modelling rule";
    }
    const Node* target = as.findChild(set->nodeId, QualifiedName{ns, "TargetPosition"});
    const Node* xyz = as.findChild(target->nodeId, {0, "CartesianCoordinates"});
    ASSERT_NE(xyz, nullptr);
    EXPECT_NE(as.findChild(xyz->nodeId, {0, "X"}), nullptr);
    EXPECT_EQ(unitOf(as, as.findChild(xyz->nodeId, {0, "LengthUnit"})), kMetre);
    EXPECT_NE(as.findChild(*id, {0, "CurrentState"}), nullptr);
    // Abstract skill types cannot be instantiated.
    auto abstract = instantiate(as, *skillsNodeId(as, cm::kSkillType), NodeId(ns0::ObjectsFolder),
                                NodeId(ns0::Organizes), QualifiedName{1, "Skill"}, named("Skill"));
    EXPECT_EQ(abstract.status(), status::BadTypeDefinitionInvalid);
}

TEST(SkillModels, SurviveExportAndReload) {
    // All companion namespaces in one file: the exporter writes the inverse side of
    // references into later models (a DI type's HasSubtype to a Robotics type), so one
    // namespace alone would not load before the next.
    const AddressSpace a = fullSpace();
    NodeSetExportOptions options;
    for (const auto& m : kCompanionModels) options.namespaces.push_back(*a.namespaceIndex(m.uri));
    std::string xml;
    const auto ex = exportNodeSet(a, options, xml);
    ASSERT_TRUE(ex.ok()) << ex.error;
    AddressSpace b = baseSpace();
    const auto st = loadNodeSet(b, xml, "companion-export.xml");
    ASSERT_TRUE(st.ok()) << st.error;
    EXPECT_EQ(st.nodes, ex.nodes);
    std::size_t total = 0;
    for (const auto& m : kCompanionModels) {
        const auto ns = *a.namespaceIndex(m.uri);
        ASSERT_EQ(b.namespaceIndex(m.uri), std::optional<std::uint16_t>(ns));
        a.forEachNode([&](const Node& n) {
            if (n.nodeId.namespaceIndex() != ns) return;
            ++total;
            const Node* o = b.find(n.nodeId);
            ASSERT_NE(o, nullptr) << n.nodeId.toString();
            const auto what = n.nodeId.toString();
            EXPECT_EQ(o->nodeClass, n.nodeClass) << what;
            EXPECT_EQ(o->browseName, n.browseName) << what;
            EXPECT_EQ(o->displayName, n.displayName) << what;
            EXPECT_EQ(o->description, n.description) << what;
            EXPECT_EQ(o->isAbstract, n.isAbstract) << what;
            EXPECT_EQ(o->dataType, n.dataType) << what;
            EXPECT_EQ(o->valueRank, n.valueRank) << what;
            EXPECT_EQ(o->arrayDimensions, n.arrayDimensions) << what;
            EXPECT_EQ(o->accessLevel, n.accessLevel) << what;
            EXPECT_EQ(o->value.value, n.value.value) << what;
            EXPECT_EQ(o->definition, n.definition) << what;
            EXPECT_EQ(o->references.size(), n.references.size()) << what;
        });
        ASSERT_NE(b.findModel(m.uri), nullptr);
        EXPECT_EQ(b.findModel(m.uri)->version, a.findModel(m.uri)->version);
    }
    EXPECT_EQ(total, ex.nodes);
    // The reloaded types still decode and still form the skill hierarchy.
    const NodeId pick = typeId(b, cm::kCompositeSkillsUri, "PickAndPlaceSkillType");
    EXPECT_TRUE(b.isSubtypeOf(pick, NodeId(ns0::ProgramStateMachineType)));
    EXPECT_NE(b.dataTypes().find(typeId(b, cm::kGripperSkillsUri, "GripPointTypeEnumeration")),
              nullptr);
}

}  // namespace skill_models_test
