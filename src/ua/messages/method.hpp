#pragma once
// Method service set (OPC 10000-4, 5.11): Call; and Argument (OPC 10000-3, 8.6), the
// structure that describes a method's input and output arguments.
#include "ua/messages/common.hpp"

namespace skillcell::ua {

struct Argument {
    static constexpr std::uint32_t kBinaryEncodingId = 298;
    String name;
    NodeId dataType;
    std::int32_t valueRank = -1;  // -1 scalar, 1 one-dimensional array, ...
    std::vector<std::uint32_t> arrayDimensions;
    LocalizedText description;
    static auto tie(auto& s) {
        return std::tie(s.name, s.dataType, s.valueRank, s.arrayDimensions, s.description);
    }
    friend bool operator==(const Argument&, const Argument&) = default;
};

struct CallMethodRequest {
    NodeId objectId;
    NodeId methodId;
    std::vector<Variant> inputArguments;
    static auto tie(auto& s) { return std::tie(s.objectId, s.methodId, s.inputArguments); }
};

struct CallMethodResult {
    StatusCode statusCode;
    std::vector<StatusCode> inputArgumentResults;
    std::vector<DiagnosticInfo> inputArgumentDiagnosticInfos;
    std::vector<Variant> outputArguments;
    static auto tie(auto& s) {
        return std::tie(s.statusCode, s.inputArgumentResults, s.inputArgumentDiagnosticInfos,
                        s.outputArguments);
    }
};

struct CallRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 712;
    RequestHeader requestHeader;
    std::vector<CallMethodRequest> methodsToCall;
    static auto tie(auto& s) { return std::tie(s.requestHeader, s.methodsToCall); }
};

struct CallResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 715;
    ResponseHeader responseHeader;
    std::vector<CallMethodResult> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

}  // namespace skillcell::ua
