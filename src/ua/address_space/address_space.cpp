#include "ua/address_space/address_space.hpp"

#include <algorithm>

#include "ua/encoding/codec.hpp"

namespace skillcell::ua {

bool hasAttribute(NodeClass nc, std::uint32_t attributeId) {
    using A = AttributeId;
    const auto is = [nc](std::initializer_list<NodeClass> classes) {
        return std::find(classes.begin(), classes.end(), nc) != classes.end();
    };
    switch (static_cast<A>(attributeId)) {
        case A::NodeId:
        case A::NodeClass:
        case A::BrowseName:
        case A::DisplayName:
        case A::Description:
        case A::WriteMask:
        case A::UserWriteMask:
            return true;
        case A::IsAbstract:
            return is({NodeClass::ObjectType, NodeClass::VariableType, NodeClass::ReferenceType,
                       NodeClass::DataType});
        case A::Symmetric:
        case A::InverseName:
            return nc == NodeClass::ReferenceType;
        case A::ContainsNoLoops:
            return nc == NodeClass::View;
        case A::EventNotifier:
            return is({NodeClass::Object, NodeClass::View});
        case A::Value:
        case A::DataType:
        case A::ValueRank:
        case A::ArrayDimensions:
            return is({NodeClass::Variable, NodeClass::VariableType});
        case A::AccessLevel:
        case A::UserAccessLevel:
        case A::MinimumSamplingInterval:
        case A::Historizing:
        case A::AccessLevelEx:
            return nc == NodeClass::Variable;
        case A::Executable:
        case A::UserExecutable:
            return nc == NodeClass::Method;
        case A::DataTypeDefinition:
        case A::RolePermissions:
        case A::UserRolePermissions:
        case A::AccessRestrictions:
            return false;
    }
    return false;
}

AddressSpace::AddressSpace(std::string applicationUri)
    : namespaces_{String(kNs0Uri), std::move(applicationUri)} {}

std::uint16_t AddressSpace::registerNamespace(std::string_view uri) {
    if (auto i = namespaceIndex(uri)) return *i;
    namespaces_.emplace_back(uri);
    return static_cast<std::uint16_t>(namespaces_.size() - 1);
}

std::optional<std::uint16_t> AddressSpace::namespaceIndex(std::string_view uri) const {
    for (std::size_t i = 0; i < namespaces_.size(); ++i) {
        if (namespaces_[i] == uri) return static_cast<std::uint16_t>(i);
    }
    return std::nullopt;
}

Node* AddressSpace::find(const NodeId& id) {
    auto it = nodes_.find(id);
    return it == nodes_.end() ? nullptr : &it->second;
}

const Node* AddressSpace::find(const NodeId& id) const {
    auto it = nodes_.find(id);
    return it == nodes_.end() ? nullptr : &it->second;
}

Result<Node*> AddressSpace::addNode(Node node) {
    if (node.nodeId.isNull()) return status::BadNodeIdInvalid;
    NodeId id = node.nodeId;
    auto [it, inserted] = nodes_.try_emplace(std::move(id), std::move(node));
    if (!inserted) return status::BadNodeIdExists;
    return &it->second;
}

StatusCode AddressSpace::addReference(const NodeId& source, const NodeId& referenceTypeId,
                                      const NodeId& target, bool isForward) {
    Node* src = find(source);
    if (src == nullptr) return status::BadNodeIdUnknown;
    if (!isReferenceType(referenceTypeId)) return status::BadReferenceTypeIdInvalid;
    const Reference here{referenceTypeId, target, isForward};
    if (std::find(src->references.begin(), src->references.end(), here) != src->references.end()) {
        return status::Good;
    }
    src->references.push_back(here);
    Node* dst = find(target);
    if (dst != nullptr) dst->references.push_back(Reference{referenceTypeId, source, !isForward});
    if (referenceTypeId == NodeId(ns0::HasSubtype)) {
        if (isForward && dst != nullptr) dst->superType = source;
        if (!isForward) src->superType = target;
    }
    return status::Good;
}

StatusCode AddressSpace::removeNode(const NodeId& id) {
    const auto it = nodes_.find(id);
    if (it == nodes_.end()) return status::BadNodeIdUnknown;
    for (const auto& r : it->second.references) {
        Node* other = r.target == id ? nullptr : find(r.target);
        if (other == nullptr) continue;
        std::erase_if(other->references,
                      [&id](const Reference& back) { return back.target == id; });
    }
    nodes_.erase(it);
    return status::Good;
}

bool AddressSpace::isSubtypeOf(const NodeId& type, const NodeId& superType) const {
    // Hierarchies are shallow (under 10 levels in namespace 0); the bound only guards
    // against a cycle in a malformed model.
    NodeId current = type;
    for (int depth = 0; depth < 64; ++depth) {
        if (current == superType) return true;
        const Node* n = find(current);
        if (n == nullptr || n->superType.isNull()) return false;
        current = n->superType;
    }
    return false;
}

bool AddressSpace::isReferenceType(const NodeId& id) const {
    const Node* n = find(id);
    return n != nullptr && n->nodeClass == NodeClass::ReferenceType;
}

NodeId AddressSpace::typeDefinitionOf(const Node& node) const {
    for (const auto& r : node.references) {
        if (r.isForward && r.referenceTypeId == NodeId(ns0::HasTypeDefinition)) return r.target;
    }
    return {};
}

const Node* AddressSpace::findChild(const NodeId& parent, const QualifiedName& browseName) const {
    const Node* p = find(parent);
    if (p == nullptr) return nullptr;
    for (const auto& r : p->references) {
        if (!r.isForward || !isSubtypeOf(r.referenceTypeId, NodeId(ns0::HierarchicalReferences))) {
            continue;
        }
        const Node* child = find(r.target);
        if (child != nullptr && child->browseName == browseName) return child;
    }
    return nullptr;
}

bool AddressSpace::valueMatches(const Variant& value, const NodeId& dataType,
                                std::int32_t valueRank) const {
    const NodeId baseDataType(ns0::BaseDataType);
    if (value.isEmpty()) return dataType == baseDataType;

    const std::size_t dims =
        value.isArray() ? std::max<std::size_t>(1, value.dimensions().size()) : 0;
    switch (valueRank) {
        case value_rank::kScalarOrOneDimension:
            if (dims > 1) return false;
            break;
        case value_rank::kAny:
            break;
        case value_rank::kScalar:
            if (dims != 0) return false;
            break;
        case value_rank::kOneOrMoreDimensions:
            if (dims == 0) return false;
            break;
        default:
            if (valueRank < 0 || dims != static_cast<std::size_t>(valueRank)) return false;
    }

    // Built-in type ids double as the NodeIds of their data types (OPC 10000-6, 5.1.2).
    const NodeId builtin(static_cast<std::uint32_t>(value.type()));
    if (isSubtypeOf(builtin, dataType)) return true;
    if (value.type() == BuiltinType::Variant) return false;  // only BaseDataType takes any
    if (isSubtypeOf(dataType, builtin)) return true;         // Duration <- Double, Structures <- EO
    return value.type() == BuiltinType::Int32 && isSubtypeOf(dataType, NodeId(ns0::Enumeration));
}

const NodeId* AddressSpace::dataTypeOfEncoding(const NodeId& encodingId) const {
    if (const DataTypeInfo* info = dataTypes_.findByEncoding(encodingId)) return &info->dataTypeId;
    const Node* encoding = find(encodingId);
    if (encoding == nullptr) return nullptr;
    for (const auto& r : encoding->references) {
        if (!r.isForward && r.referenceTypeId == NodeId(ns0::HasEncoding)) return &r.target;
    }
    return nullptr;
}

bool AddressSpace::structuresMatch(const Variant& value, const NodeId& dataType) const {
    if (value.type() != BuiltinType::ExtensionObject) return true;
    if (dataType == NodeId(ns0::Structure) || dataType == NodeId(ns0::BaseDataType)) return true;
    // For an encoding nobody here knows: refused only where the data type's own encodings
    // are known (a concrete structure such as 3DFrame), since none of them is this one.
    const auto unknownEncodingFits = [&] {
        const Node* type = find(dataType);
        if (type == nullptr || type->isAbstract) return true;
        if (const DataTypeInfo* info = dataTypes_.find(dataType);
            info != nullptr &&
            (!info->binaryEncodingId.isNull() || !info->xmlEncodingId.isNull())) {
            return false;
        }
        return std::none_of(type->references.begin(), type->references.end(),
                            [](const Reference& r) {
                                return r.isForward && r.referenceTypeId == NodeId(ns0::HasEncoding);
                            });
    };
    const auto fits = [&](const Scalar& s) {
        const auto* eo = std::get_if<ExtensionObject>(&s);
        if (eo == nullptr || (eo->empty() && eo->typeId.isNull())) return true;
        const NodeId* type = dataTypeOfEncoding(eo->typeId);
        return type != nullptr ? isSubtypeOf(*type, dataType) : unknownEncodingFits();
    };
    if (!value.isArray()) return fits(value.scalar());
    return std::all_of(value.elements().begin(), value.elements().end(), fits);
}

DataValue AddressSpace::readValue(const Node& node) const {
    if (node.valueSource) return node.valueSource();
    return node.value;
}

StatusCode AddressSpace::setValue(const NodeId& id, Variant value) {
    Node* n = find(id);
    if (n == nullptr) return status::BadNodeIdUnknown;
    if (n->nodeClass != NodeClass::Variable && n->nodeClass != NodeClass::VariableType) {
        return status::BadNodeClassInvalid;
    }
    if (!valueMatches(value, n->dataType, n->valueRank)) return status::BadTypeMismatch;
    n->value = DataValue{};
    n->value.value = std::move(value);
    n->value.sourceTimestamp = DateTime::now();
    notifyValueChanged(*n);
    return status::Good;
}

StatusCode AddressSpace::setValueSource(const NodeId& id, ValueSource source) {
    Node* n = find(id);
    if (n == nullptr) return status::BadNodeIdUnknown;
    if (n->nodeClass != NodeClass::Variable) return status::BadNodeClassInvalid;
    n->valueSource = std::move(source);
    return status::Good;
}

StatusCode AddressSpace::setValueSink(const NodeId& id, ValueSink sink) {
    Node* n = find(id);
    if (n == nullptr) return status::BadNodeIdUnknown;
    if (n->nodeClass != NodeClass::Variable) return status::BadNodeClassInvalid;
    n->valueSink = std::move(sink);
    return status::Good;
}

StatusCode AddressSpace::setMethodCallback(const NodeId& id, MethodCallback callback) {
    Node* n = find(id);
    if (n == nullptr) return status::BadNodeIdUnknown;
    if (n->nodeClass != NodeClass::Method) return status::BadNodeClassInvalid;
    n->method = std::move(callback);
    return status::Good;
}

bool AddressSpace::isFolder(const NodeId& id) const {
    const Node* n = find(id);
    return n != nullptr && isSubtypeOf(typeDefinitionOf(*n), NodeId(ns0::FolderType));
}

Result<Node*> AddressSpace::addInstance(Node node, const NodeId& parent,
                                        const NodeId& referenceType, const NodeId& typeDefinition) {
    if (find(parent) == nullptr) return status::BadNodeIdUnknown;
    if (!typeDefinition.isNull() && find(typeDefinition) == nullptr) {
        return status::BadTypeDefinitionInvalid;
    }
    const NodeId ref = !referenceType.isNull() ? referenceType
                       : isFolder(parent)      ? NodeId(ns0::Organizes)
                                               : NodeId(ns0::HasComponent);
    if (!isReferenceType(ref)) return status::BadReferenceTypeIdInvalid;
    if (node.displayName.text.empty()) node.displayName.text = node.browseName.name;
    auto added = addNode(std::move(node));
    if (!added) return added;
    Node* n = *added;
    (void)addReference(parent, ref, n->nodeId);
    if (!typeDefinition.isNull()) {
        (void)addReference(n->nodeId, NodeId(ns0::HasTypeDefinition), typeDefinition);
    }
    return n;
}

Result<Node*> AddressSpace::addObject(const NodeId& parent, const NodeId& id,
                                      std::string_view browseName, const NodeId& typeDefinition,
                                      const NodeId& referenceType) {
    Node n;
    n.nodeId = id;
    n.nodeClass = NodeClass::Object;
    n.browseName = QualifiedName{id.namespaceIndex(), String(browseName)};
    return addInstance(std::move(n), parent, referenceType, typeDefinition);
}

Result<Node*> AddressSpace::addFolder(const NodeId& parent, const NodeId& id,
                                      std::string_view browseName) {
    return addObject(parent, id, browseName, NodeId(ns0::FolderType), NodeId(ns0::Organizes));
}

Result<Node*> AddressSpace::addVariable(const NodeId& parent, const NodeId& id,
                                        std::string_view browseName, const NodeId& dataType,
                                        Variant value, std::uint8_t accessLevel,
                                        std::int32_t valueRank, const NodeId& typeDefinition,
                                        const NodeId& referenceType) {
    if (!value.isEmpty() && !valueMatches(value, dataType, valueRank)) {
        return status::BadTypeMismatch;
    }
    Node n;
    n.nodeId = id;
    n.nodeClass = NodeClass::Variable;
    n.browseName = QualifiedName{id.namespaceIndex(), String(browseName)};
    n.dataType = dataType;
    n.valueRank = valueRank;
    n.accessLevel = accessLevel;
    n.userAccessLevel = accessLevel;
    if (value.isArray()) n.arrayDimensions = {static_cast<std::uint32_t>(value.elements().size())};
    if (valueRank == value_rank::kScalar) n.arrayDimensions.clear();
    n.value.value = std::move(value);
    n.value.sourceTimestamp = DateTime::now();
    return addInstance(std::move(n), parent, referenceType, typeDefinition);
}

Result<Node*> AddressSpace::addProperty(const NodeId& parent, const NodeId& id,
                                        std::string_view browseName, const NodeId& dataType,
                                        Variant value, std::int32_t valueRank) {
    return addVariable(parent, id, browseName, dataType, std::move(value),
                       access_level::kCurrentRead, valueRank, NodeId(ns0::PropertyType),
                       NodeId(ns0::HasProperty));
}

Variant argumentsValue(const std::vector<Argument>& arguments) {
    std::vector<ExtensionObject> eos;
    eos.reserve(arguments.size());
    for (const auto& a : arguments) eos.push_back(toExtensionObject(a));
    return Variant::array(std::move(eos));
}

Result<Node*> AddressSpace::addMethod(const NodeId& parent, const NodeId& id,
                                      std::string_view browseName, std::vector<Argument> inputs,
                                      std::vector<Argument> outputs, MethodCallback callback) {
    Node n;
    n.nodeId = id;
    n.nodeClass = NodeClass::Method;
    n.browseName = QualifiedName{id.namespaceIndex(), String(browseName)};
    n.method = std::move(callback);
    auto added = addInstance(std::move(n), parent, NodeId(ns0::HasComponent), NodeId());
    if (!added) return added;

    // The argument properties carry standard (namespace 0) browse names: clients find them
    // by "0:InputArguments".
    for (auto* list : {&inputs, &outputs}) {
        if (list->empty()) continue;
        const char* name = list == &inputs ? "InputArguments" : "OutputArguments";
        Node p;
        p.nodeId = childNodeId(id, name);
        p.nodeClass = NodeClass::Variable;
        p.browseName = QualifiedName{0, name};
        p.dataType = NodeId(ns0::ArgumentType);
        p.valueRank = value_rank::kOneDimension;
        p.arrayDimensions = {static_cast<std::uint32_t>(list->size())};
        p.value.value = argumentsValue(*list);
        auto prop =
            addInstance(std::move(p), id, NodeId(ns0::HasProperty),
                        find(NodeId(ns0::PropertyType)) ? NodeId(ns0::PropertyType) : NodeId());
        if (!prop) return prop.status();
    }
    return find(id);
}

void AddressSpace::registerModel(Model model) {
    for (auto& m : models_) {
        if (m.uri == model.uri) {
            m = std::move(model);
            return;
        }
    }
    models_.push_back(std::move(model));
}

const AddressSpace::Model* AddressSpace::findModel(std::string_view uri) const {
    for (const auto& m : models_) {
        if (m.uri == uri) return &m;
    }
    return nullptr;
}

NodeId AddressSpace::childNodeId(const NodeId& parent, std::string_view name) {
    std::string base;
    if (const auto* s = std::get_if<String>(&parent.identifier())) {
        base = *s;
    } else {
        base = parent.toString();
        if (base.starts_with("ns=")) base = base.substr(base.find(';') + 1);
    }
    base += '/';
    base += name;
    return NodeId(parent.namespaceIndex(), std::move(base));
}

Result<std::vector<Argument>> AddressSpace::methodArguments(const NodeId& methodId,
                                                            std::string_view propertyName) const {
    std::vector<Argument> out;
    const Node* prop = findChild(methodId, QualifiedName{0, String(propertyName)});
    if (prop == nullptr) return out;
    const DataValue dv = readValue(*prop);
    if (!dv.value || dv.value->isEmpty()) return out;
    const Variant& v = *dv.value;
    if (!v.isArray() || v.type() != BuiltinType::ExtensionObject) {
        return status::BadDecodingError;
    }
    out.reserve(v.elements().size());
    for (const auto& e : v.elements()) {
        const auto* eo = std::get_if<ExtensionObject>(&e);
        if (eo == nullptr) return status::BadDecodingError;
        Argument a;
        if (fromExtensionObject(*eo, a).isBad()) return status::BadDecodingError;
        out.push_back(std::move(a));
    }
    return out;
}

}  // namespace skillcell::ua
