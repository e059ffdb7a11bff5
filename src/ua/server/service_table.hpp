#pragma once
// ServiceTable: request encoding id -> handler. Service sets register their typed handlers
// here (one file per set under services/); the connection only calls dispatch(). A new
// service set joins by registering, without touching the transport.
#include <cstdint>
#include <functional>
#include <span>
#include <unordered_map>
#include <utility>
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

/// The response of a deferred service (Publish): sent later, at most once, by whoever holds
/// it. Move-only, so that two owners cannot both answer; a moved-from or used Deferred is
/// empty. Dropping it unanswered sends nothing (the client's request then times out), and
/// answering after the connection closed is a no-op (the sender holds a weak reference).
template <EncodableStructure Response>
class Deferred {
public:
    Deferred() = default;
    Deferred(ResponseSender sender, std::uint32_t requestHandle)
        : sender_(std::move(sender)), requestHandle_(requestHandle) {}
    Deferred(const Deferred&) = delete;
    Deferred& operator=(const Deferred&) = delete;
    Deferred(Deferred&& other) noexcept
        : sender_(std::exchange(other.sender_, nullptr)), requestHandle_(other.requestHandle_) {}
    Deferred& operator=(Deferred&& other) noexcept {
        sender_ = std::exchange(other.sender_, nullptr);
        requestHandle_ = other.requestHandle_;
        return *this;
    }
    ~Deferred() = default;

    [[nodiscard]] bool pending() const { return static_cast<bool>(sender_); }
    [[nodiscard]] std::uint32_t requestHandle() const { return requestHandle_; }

    /// Sends `response` with its header's handle and timestamp filled in.
    void send(Response response) {
        if (!sender_) return;
        response.responseHeader.timestamp = DateTime::now();
        response.responseHeader.requestHandle = requestHandle_;
        std::vector<std::uint8_t> body;
        encodeServiceMessage(body, response);
        std::exchange(sender_, nullptr)(std::move(body));
    }
    /// Answers with a ServiceFault.
    void fail(StatusCode status) {
        if (!sender_) return;
        std::exchange(sender_, nullptr)(encodeServiceFault(requestHandle_, status));
    }

private:
    ResponseSender sender_;
    std::uint32_t requestHandle_ = 0;
};

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
        entries_[Request::kBinaryEncodingId] =
            Entry{access,
                  [h = std::move(handler)](ServiceContext& ctx, BinaryReader& r,
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

    template <EncodableStructure Request, EncodableStructure Response>
    using DeferredHandler =
        std::function<StatusCode(ServiceContext&, const Request&, Deferred<Response>)>;

    /// Registers a handler that answers later through its Deferred (Publish). A Bad status
    /// returned becomes a ServiceFault; the handler returns one only if it did not keep or
    /// use the Deferred. Good with nothing sent yet leaves the request pending.
    template <EncodableStructure Request, EncodableStructure Response>
    void addDeferred(Access access, DeferredHandler<Request, Response> handler) {
        entries_[Request::kBinaryEncodingId] =
            Entry{access,
                  [h = std::move(handler)](ServiceContext& ctx, BinaryReader& r,
                                           std::vector<std::uint8_t>&) -> StatusCode {
                      Request request{};
                      decode(r, request);
                      if (!r.ok()) return r.status();
                      if (r.remaining() != 0) return status::BadDecodingError;
                      if (!ctx.reply) return status::BadInternalError;
                      ctx.requestHandle = request.requestHeader.requestHandle;
                      ctx.requestHeader = &request.requestHeader;
                      return h(ctx, request,
                               Deferred<Response>(ctx.reply, request.requestHeader.requestHandle));
                  },
                  true};
    }

    /// The entry for a request encoding id, or nullptr for an unknown service.
    /// invoke() leaves `out` empty when the response is deferred.
    struct Entry {
        Access access = Access::ActivatedSession;
        std::function<StatusCode(ServiceContext&, BinaryReader&, std::vector<std::uint8_t>&)>
            invoke;
        bool deferred = false;  // answers through ServiceContext::reply
    };
    [[nodiscard]] const Entry* find(std::uint32_t encodingId) const {
        auto it = entries_.find(encodingId);
        return it == entries_.end() ? nullptr : &it->second;
    }

private:
    std::unordered_map<std::uint32_t, Entry> entries_;
};

}  // namespace skillcell::ua
