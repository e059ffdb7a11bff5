#include "ua/server/request_dispatch.hpp"

#include "ua/messages/discovery.hpp"

namespace skillcell::ua {

bool isDiscoveryService(std::uint32_t requestTypeId) {
    return requestTypeId == GetEndpointsRequest::kBinaryEncodingId ||
           requestTypeId == FindServersRequest::kBinaryEncodingId ||
           requestTypeId == FindServersOnNetworkRequest::kBinaryEncodingId;
}

DispatchedRequest dispatchRequest(const ServiceTable& services, SessionManager& sessions,
                                  const ServerLimits& limits, const RequestChannel& channel,
                                  std::span<const std::uint8_t> body, SteadyTime now,
                                  const ReplyFactory& replyFor) {
    DispatchedRequest out;
    BinaryReader r(body);
    NodeId typeId;
    decode(r, typeId);
    if (!r.ok()) {
        out.status = r.status();  // not even a type id: the stream is corrupt
        return out;
    }
    // Every request starts with a RequestHeader; peek at it so that even a fault for an
    // unknown or undecodable request carries the client's request handle.
    RequestHeader header;
    BinaryReader peek = r;
    decode(peek, header);
    out.requestHandle = peek.ok() ? header.requestHandle : 0;
    auto fault = [&](StatusCode s) {
        out.response = encodeServiceFault(out.requestHandle, s);
        return out;
    };
    const ServiceTable::Entry* entry = typeId.isNumeric() && typeId.namespaceIndex() == 0
                                           ? services.find(typeId.numeric())
                                           : nullptr;
    if (entry == nullptr) return fault(status::BadServiceUnsupported);
    if (!peek.ok()) return fault(status::BadDecodingError);
    if (channel.discoveryOnly && !isDiscoveryService(typeId.numeric())) {
        return fault(status::BadSecurityPolicyRejected);
    }

    ServiceContext ctx;
    ctx.channelId = channel.channelId;
    ctx.limits = &limits;
    ctx.now = now;
    ctx.endpointUrl = channel.endpointUrl;
    ctx.securityPolicyUri = channel.securityPolicyUri;
    ctx.clientCertificate = channel.clientCertificate;
    ctx.clientKey = channel.clientKey;
    ctx.securityMode = channel.securityMode;
    if (entry->access == ServiceTable::Access::ActivatedSession) {
        auto session = sessions.authorize(header.authenticationToken, channel.channelId, now);
        if (!session) return fault(session.status());
        ctx.session = *session;
    }
    if (entry->deferred) ctx.reply = replyFor(out.requestHandle);
    const StatusCode s = entry->invoke(ctx, r, out.response);
    if (s.isBad()) return fault(s);
    return out;  // an empty response: deferred, answered through ctx.reply
}

}  // namespace skillcell::ua
