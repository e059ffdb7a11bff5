#include "ua/server/services/method_service.hpp"

#include <spdlog/spdlog.h>

#include "ua/server/services/operations.hpp"
#include "ua/server/services/register_services.hpp"

namespace skillcell::ua {
namespace {

bool hasComponent(const AddressSpace& as, const Node& owner, const NodeId& method) {
    for (const auto& r : owner.references) {
        if (r.isForward && r.target == method &&
            as.isSubtypeOf(r.referenceTypeId, NodeId(ns0::HasComponent))) {
            return true;
        }
    }
    return false;
}

/// The method belongs to the object, or to the object's type or one of its supertypes
/// (a method declared on a type is callable on every instance; OPC 10000-4, 5.11.2).
bool belongsTo(const AddressSpace& as, const Node& object, const NodeId& method) {
    if (hasComponent(as, object, method)) return true;
    NodeId type =
        object.nodeClass == NodeClass::ObjectType ? object.superType : as.typeDefinitionOf(object);
    for (int depth = 0; depth < 64 && !type.isNull(); ++depth) {
        const Node* t = as.find(type);
        if (t == nullptr) return false;
        if (hasComponent(as, *t, method)) return true;
        type = t->superType;
    }
    return false;
}

}  // namespace

CallMethodResult callMethod(AddressSpace& as, const CallMethodRequest& request,
                            const Caller& caller) {
    CallMethodResult result;
    const Node* object = as.find(request.objectId);
    if (object == nullptr) {
        result.statusCode = status::BadNodeIdUnknown;
        return result;
    }
    if (object->nodeClass != NodeClass::Object && object->nodeClass != NodeClass::ObjectType) {
        result.statusCode = status::BadNodeIdInvalid;
        return result;
    }
    const Node* method = as.find(request.methodId);
    if (method == nullptr || method->nodeClass != NodeClass::Method ||
        !belongsTo(as, *object, request.methodId)) {
        result.statusCode = status::BadMethodInvalid;
        return result;
    }
    if (!method->executable || !method->userExecutable) {
        result.statusCode = status::BadNotExecutable;
        return result;
    }
    // Calling a method acts on the plant (a skill's Start moves a robot): operators, or
    // engineers for configuration methods.
    if (!caller.roles.atLeast(method->requiredRole)) {
        spdlog::warn("session {}: Call of {} refused (BadUserAccessDenied): roles {}, needs {}",
                     caller.sessionId.toString(), request.methodId.toString(),
                     caller.roles.toString(), roleName(method->requiredRole));
        result.statusCode = status::BadUserAccessDenied;
        return result;
    }

    auto arguments = as.methodArguments(request.methodId, "InputArguments");
    if (!arguments) {
        result.statusCode = status::BadInternalError;
        return result;
    }
    const auto& inputs = request.inputArguments;
    if (inputs.size() < arguments->size()) {
        result.statusCode = status::BadArgumentsMissing;
        return result;
    }
    if (inputs.size() > arguments->size()) {
        result.statusCode = status::BadTooManyArguments;
        return result;
    }
    // OPC 10000-4, 5.11.2.2: a wrongly typed argument makes the call BadInvalidArgument,
    // with BadTypeMismatch in that argument's inputArgumentResults entry. A structure is
    // wrongly typed, too, when its encoding is not one of the argument's DataType or of a
    // subtype (a 3DVector where a 3DFrame is due), not only a value of another built-in type.
    bool allGood = true;
    result.inputArgumentResults.reserve(inputs.size());
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        const Argument& a = (*arguments)[i];
        const bool ok = as.valueMatches(inputs[i], a.dataType, a.valueRank) &&
                        as.structuresMatch(inputs[i], a.dataType);
        result.inputArgumentResults.push_back(ok ? status::Good : status::BadTypeMismatch);
        allGood = allGood && ok;
    }
    if (!allGood) {
        result.statusCode = status::BadInvalidArgument;
        return result;
    }
    if (!method->method) {
        result.statusCode = status::BadNotImplemented;
        return result;
    }
    // Copy the callback: it may change the address space (and so move this node's fields).
    const MethodCallback callback = method->method;
    result.statusCode = callback(caller, request.objectId, inputs, result.outputArguments);
    if (result.statusCode.isBad()) result.outputArguments.clear();
    return result;
}

StatusCode call(AddressSpace& as, const ServerLimits& limits, const CallRequest& request,
                CallResponse& response, const Caller& caller) {
    return forEachOperation(limits, request.methodsToCall, response.results,
                            [&](const CallMethodRequest& r) { return callMethod(as, r, caller); });
}

void registerMethodServices(ServiceTable& table, AddressSpace& as) {
    table.add<CallRequest, CallResponse>(ServiceTable::Access::ActivatedSession,
                                         [&as](ServiceContext& ctx, const auto& req, auto& resp) {
                                             return call(as, limitsOf(ctx), req, resp,
                                                         callerOf(ctx));
                                         });
}

}  // namespace skillcell::ua
