#pragma once
// Subscription and MonitoredItem service sets (OPC 10000-4, 5.12 and 5.13) and the
// notifications a Publish response carries (7.20-7.25). Binary encoding ids checked against
// Schema/NodeIds.csv. The filters are in event_filter.hpp.
#include <cstdint>
#include <tuple>
#include <vector>

#include "ua/messages/attribute.hpp"
#include "ua/messages/common.hpp"
#include "ua/messages/event_filter.hpp"

namespace skillcell::ua {

enum class MonitoringMode : std::int32_t { Disabled = 0, Sampling = 1, Reporting = 2 };

// --- MonitoredItem service set -----------------------------------------------------------

struct MonitoringParameters {
    std::uint32_t clientHandle = 0;
    double samplingInterval = -1;  // -1: the publishing interval, 0: the fastest
    ExtensionObject filter;        // empty, DataChangeFilter, EventFilter or AggregateFilter
    std::uint32_t queueSize = 1;
    bool discardOldest = true;
    static auto tie(auto& s) {
        return std::tie(s.clientHandle, s.samplingInterval, s.filter, s.queueSize, s.discardOldest);
    }
};

struct MonitoredItemCreateRequest {
    ReadValueId itemToMonitor;
    MonitoringMode monitoringMode = MonitoringMode::Reporting;
    MonitoringParameters requestedParameters;
    static auto tie(auto& s) {
        return std::tie(s.itemToMonitor, s.monitoringMode, s.requestedParameters);
    }
};

struct MonitoredItemCreateResult {
    StatusCode statusCode;
    std::uint32_t monitoredItemId = 0;
    double revisedSamplingInterval = 0;
    std::uint32_t revisedQueueSize = 0;
    ExtensionObject filterResult;  // EventFilterResult for event items
    static auto tie(auto& s) {
        return std::tie(s.statusCode, s.monitoredItemId, s.revisedSamplingInterval,
                        s.revisedQueueSize, s.filterResult);
    }
};

struct CreateMonitoredItemsRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 751;
    RequestHeader requestHeader;
    std::uint32_t subscriptionId = 0;
    TimestampsToReturn timestampsToReturn = TimestampsToReturn::Both;
    std::vector<MonitoredItemCreateRequest> itemsToCreate;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.subscriptionId, s.timestampsToReturn, s.itemsToCreate);
    }
};

struct CreateMonitoredItemsResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 754;
    ResponseHeader responseHeader;
    std::vector<MonitoredItemCreateResult> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

struct MonitoredItemModifyRequest {
    std::uint32_t monitoredItemId = 0;
    MonitoringParameters requestedParameters;
    static auto tie(auto& s) { return std::tie(s.monitoredItemId, s.requestedParameters); }
};

struct MonitoredItemModifyResult {
    StatusCode statusCode;
    double revisedSamplingInterval = 0;
    std::uint32_t revisedQueueSize = 0;
    ExtensionObject filterResult;
    static auto tie(auto& s) {
        return std::tie(s.statusCode, s.revisedSamplingInterval, s.revisedQueueSize,
                        s.filterResult);
    }
};

struct ModifyMonitoredItemsRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 763;
    RequestHeader requestHeader;
    std::uint32_t subscriptionId = 0;
    TimestampsToReturn timestampsToReturn = TimestampsToReturn::Both;
    std::vector<MonitoredItemModifyRequest> itemsToModify;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.subscriptionId, s.timestampsToReturn, s.itemsToModify);
    }
};

struct ModifyMonitoredItemsResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 766;
    ResponseHeader responseHeader;
    std::vector<MonitoredItemModifyResult> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

struct SetMonitoringModeRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 769;
    RequestHeader requestHeader;
    std::uint32_t subscriptionId = 0;
    MonitoringMode monitoringMode = MonitoringMode::Reporting;
    std::vector<std::uint32_t> monitoredItemIds;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.subscriptionId, s.monitoringMode, s.monitoredItemIds);
    }
};

struct SetMonitoringModeResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 772;
    ResponseHeader responseHeader;
    std::vector<StatusCode> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

struct DeleteMonitoredItemsRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 781;
    RequestHeader requestHeader;
    std::uint32_t subscriptionId = 0;
    std::vector<std::uint32_t> monitoredItemIds;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.subscriptionId, s.monitoredItemIds);
    }
};

struct DeleteMonitoredItemsResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 784;
    ResponseHeader responseHeader;
    std::vector<StatusCode> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

// --- Subscription service set ------------------------------------------------------------

struct CreateSubscriptionRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 787;
    RequestHeader requestHeader;
    double requestedPublishingInterval = 0;
    std::uint32_t requestedLifetimeCount = 0;
    std::uint32_t requestedMaxKeepAliveCount = 0;
    std::uint32_t maxNotificationsPerPublish = 0;  // 0: no limit
    bool publishingEnabled = true;
    std::uint8_t priority = 0;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.requestedPublishingInterval, s.requestedLifetimeCount,
                        s.requestedMaxKeepAliveCount, s.maxNotificationsPerPublish,
                        s.publishingEnabled, s.priority);
    }
};

struct CreateSubscriptionResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 790;
    ResponseHeader responseHeader;
    std::uint32_t subscriptionId = 0;
    double revisedPublishingInterval = 0;
    std::uint32_t revisedLifetimeCount = 0;
    std::uint32_t revisedMaxKeepAliveCount = 0;
    static auto tie(auto& s) {
        return std::tie(s.responseHeader, s.subscriptionId, s.revisedPublishingInterval,
                        s.revisedLifetimeCount, s.revisedMaxKeepAliveCount);
    }
};

struct ModifySubscriptionRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 793;
    RequestHeader requestHeader;
    std::uint32_t subscriptionId = 0;
    double requestedPublishingInterval = 0;
    std::uint32_t requestedLifetimeCount = 0;
    std::uint32_t requestedMaxKeepAliveCount = 0;
    std::uint32_t maxNotificationsPerPublish = 0;
    std::uint8_t priority = 0;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.subscriptionId, s.requestedPublishingInterval,
                        s.requestedLifetimeCount, s.requestedMaxKeepAliveCount,
                        s.maxNotificationsPerPublish, s.priority);
    }
};

struct ModifySubscriptionResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 796;
    ResponseHeader responseHeader;
    double revisedPublishingInterval = 0;
    std::uint32_t revisedLifetimeCount = 0;
    std::uint32_t revisedMaxKeepAliveCount = 0;
    static auto tie(auto& s) {
        return std::tie(s.responseHeader, s.revisedPublishingInterval, s.revisedLifetimeCount,
                        s.revisedMaxKeepAliveCount);
    }
};

struct SetPublishingModeRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 799;
    RequestHeader requestHeader;
    bool publishingEnabled = true;
    std::vector<std::uint32_t> subscriptionIds;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.publishingEnabled, s.subscriptionIds);
    }
};

struct SetPublishingModeResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 802;
    ResponseHeader responseHeader;
    std::vector<StatusCode> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

// Notifications: each travels in an ExtensionObject of NotificationMessage.notificationData.

struct MonitoredItemNotification {
    std::uint32_t clientHandle = 0;
    DataValue value;
    static auto tie(auto& s) { return std::tie(s.clientHandle, s.value); }
};

struct DataChangeNotification {
    static constexpr std::uint32_t kBinaryEncodingId = 811;
    std::vector<MonitoredItemNotification> monitoredItems;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.monitoredItems, s.diagnosticInfos); }
};

struct EventFieldList {
    std::uint32_t clientHandle = 0;
    std::vector<Variant> eventFields;  // in select clause order
    static auto tie(auto& s) { return std::tie(s.clientHandle, s.eventFields); }
};

struct EventNotificationList {
    static constexpr std::uint32_t kBinaryEncodingId = 916;
    std::vector<EventFieldList> events;
    static auto tie(auto& s) { return std::tie(s.events); }
};

struct StatusChangeNotification {
    static constexpr std::uint32_t kBinaryEncodingId = 820;
    StatusCode status;
    DiagnosticInfo diagnosticInfo;
    static auto tie(auto& s) { return std::tie(s.status, s.diagnosticInfo); }
};

struct NotificationMessage {
    std::uint32_t sequenceNumber = 0;
    DateTime publishTime;
    std::vector<ExtensionObject> notificationData;  // empty: a keep-alive
    static auto tie(auto& s) {
        return std::tie(s.sequenceNumber, s.publishTime, s.notificationData);
    }
};

struct SubscriptionAcknowledgement {
    std::uint32_t subscriptionId = 0;
    std::uint32_t sequenceNumber = 0;
    static auto tie(auto& s) { return std::tie(s.subscriptionId, s.sequenceNumber); }
};

struct PublishRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 826;
    RequestHeader requestHeader;
    std::vector<SubscriptionAcknowledgement> subscriptionAcknowledgements;
    static auto tie(auto& s) { return std::tie(s.requestHeader, s.subscriptionAcknowledgements); }
};

struct PublishResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 829;
    ResponseHeader responseHeader;
    std::uint32_t subscriptionId = 0;
    std::vector<std::uint32_t> availableSequenceNumbers;
    bool moreNotifications = false;
    NotificationMessage notificationMessage;
    std::vector<StatusCode> results;  // one per acknowledgement
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) {
        return std::tie(s.responseHeader, s.subscriptionId, s.availableSequenceNumbers,
                        s.moreNotifications, s.notificationMessage, s.results, s.diagnosticInfos);
    }
};

struct RepublishRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 832;
    RequestHeader requestHeader;
    std::uint32_t subscriptionId = 0;
    std::uint32_t retransmitSequenceNumber = 0;
    static auto tie(auto& s) {
        return std::tie(s.requestHeader, s.subscriptionId, s.retransmitSequenceNumber);
    }
};

struct RepublishResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 835;
    ResponseHeader responseHeader;
    NotificationMessage notificationMessage;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.notificationMessage); }
};

struct DeleteSubscriptionsRequest {
    static constexpr std::uint32_t kBinaryEncodingId = 847;
    RequestHeader requestHeader;
    std::vector<std::uint32_t> subscriptionIds;
    static auto tie(auto& s) { return std::tie(s.requestHeader, s.subscriptionIds); }
};

struct DeleteSubscriptionsResponse {
    static constexpr std::uint32_t kBinaryEncodingId = 850;
    ResponseHeader responseHeader;
    std::vector<StatusCode> results;
    std::vector<DiagnosticInfo> diagnosticInfos;
    static auto tie(auto& s) { return std::tie(s.responseHeader, s.results, s.diagnosticInfos); }
};

}  // namespace skillcell::ua
