#pragma once
// ServiceTable: request encoding id -> handler. Service sets register their typed handlers
// here (one file per set under services/); the connection only calls dispatch(). A new
// service set joins by registering, without touching the transport.
#include <cstdint>
#include <functional>
#include <span>
#include <unordered_map>
#include <vector>

#include "ua/encoding/codec.hpp"
#include "ua/messages/common.hpp"
#include "ua/server/service_context.hpp"

namespace skillcell::ua {

/// Encodes a service message body: the type's binary encoding NodeId, then the structure.
template <EncodableStructure T>
void encodeServiceMessage(std::vector<std::uint8_t>& out, const T& message) {
    BinaryWriter w(out);
    encode(w, NodeId(T::kBinaryEncodingId));
    encode(w, message);
}

class ServiceTable {
public:
    enum class Access : std::uint8_t {
        NoSession,         // discovery and session establishment
        ActivatedSession,  // everything else: needs a session activated on this channel
    };

    template <EncodableStructure Request, EncodableStructure Response>
    using Handler = std::function<StatusCode(ServiceContext&, const Request&, Response&)>;

    /// Registers a typed handler. A Bad status returned by it becomes a ServiceFault.
    template <EncodableStructure Request, EncodableStructure Response>
    void add(Access access, Handler<Request, Response> handler) {
        entries_[Request::kBinaryEncodingId] = Entry{
            access, [h = std::move(handler)](ServiceContext& ctx, BinaryReader& r,
                                             std::vector<std::uint8_t>& out) -> StatusCode {
                Request request{};
                decode(r, request);
                if (!r.ok()) return r.status();
                if (r.remaining() != 0) return status::BadDecodingError;
                ctx.requestHandle = request.requestHeader.requestHandle;
                ctx.requestHeader = &request.requestHeader;
                Response response{};
                const StatusCode s = h(ctx, request, response);
                if (s.isBad()) return s;
                response.responseHeader.timestamp = DateTime::now();
                response.responseHeader.requestHandle = request.requestHeader.requestHandle;
                encodeServiceMessage(out, response);
                return status::Good;
            }};
    }

    /// The entry for a request encoding id, or nullptr for an unknown service.
    struct Entry {
        Access access = Access::ActivatedSession;
        std::function<StatusCode(ServiceContext&, BinaryReader&, std::vector<std::uint8_t>&)>
            invoke;
    };
    [[nodiscard]] const Entry* find(std::uint32_t encodingId) const {
        auto it = entries_.find(encodingId);
        return it == entries_.end() ? nullptr : &it->second;
    }

private:
    std::unordered_map<std::uint32_t, Entry> entries_;
};

/// A ServiceFault for a request that failed as a whole.
[[nodiscard]] inline std::vector<std::uint8_t> encodeServiceFault(std::uint32_t requestHandle,
                                                                  StatusCode status) {
    ServiceFault fault;
    fault.responseHeader.timestamp = DateTime::now();
    fault.responseHeader.requestHandle = requestHandle;
    fault.responseHeader.serviceResult = status;
    std::vector<std::uint8_t> out;
    encodeServiceMessage(out, fault);
    return out;
}

}  // namespace skillcell::ua
