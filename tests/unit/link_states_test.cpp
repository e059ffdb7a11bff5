// LinkStates (src/ua/discovery/link_monitor.hpp): which of the interfaces mDNS uses an
// rtnetlink datagram says came up, from messages made here as the kernel makes them.
#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <net/if.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "ua/discovery/link_monitor.hpp"

namespace skillcell::ua::mdns::link_states_test {
namespace {

/// Appends one message of `type` about interface `index` with `flags`, and `padding` bytes of
/// attributes after its ifinfomsg (a real one carries its name, MTU, ...).
void appendLink(std::vector<std::uint8_t>& datagram, std::uint16_t type, int index, unsigned flags,
                std::size_t padding = 20) {
    nlmsghdr header{};
    header.nlmsg_len = NLMSG_LENGTH(sizeof(ifinfomsg) + padding);
    header.nlmsg_type = type;
    ifinfomsg info{};
    info.ifi_index = index;
    info.ifi_flags = flags;
    const std::size_t at = datagram.size();
    datagram.resize(at + NLMSG_ALIGN(header.nlmsg_len), 0);
    std::memcpy(datagram.data() + at, &header, sizeof header);
    std::memcpy(datagram.data() + at + NLMSG_HDRLEN, &info, sizeof info);
}

constexpr unsigned kRunning = IFF_UP | IFF_RUNNING | IFF_MULTICAST;
constexpr unsigned kNoCarrier = IFF_UP | IFF_MULTICAST;  // up, but the cable is out

TEST(LinkStates, AWatchedLinkThatGetsCarrierBackComesUpOnce) {
    LinkStates links({{2, true}, {3, true}});
    std::vector<std::uint8_t> d;
    appendLink(d, RTM_NEWLINK, 2, kNoCarrier);
    EXPECT_TRUE(links.cameUp(d).empty());  // going down is not coming up
    d.clear();
    appendLink(d, RTM_NEWLINK, 2, kRunning);
    EXPECT_EQ(links.cameUp(d), (std::vector<unsigned>{2}));
    EXPECT_TRUE(links.cameUp(d).empty());  // the same state again (an MTU change, say)
}

TEST(LinkStates, OnlyWatchedLinksAndLinkMessagesCount) {
    LinkStates links({{2, false}});
    std::vector<std::uint8_t> d;
    appendLink(d, RTM_NEWLINK, 7, kRunning);  // not ours
    appendLink(d, RTM_DELLINK, 2, kRunning);  // not a state
    EXPECT_TRUE(links.cameUp(d).empty());
    // Several messages in one datagram: each one counts.
    appendLink(d, RTM_NEWLINK, 2, kRunning);
    EXPECT_EQ(links.cameUp(d), (std::vector<unsigned>{2}));
}

TEST(LinkStates, AnInterfaceSetUpAgainComesUpAndOneThatWasDownAtTheStartToo) {
    LinkStates links({{4, false}});
    std::vector<std::uint8_t> d;
    appendLink(d, RTM_NEWLINK, 4, IFF_RUNNING);  // carrier, but administratively down
    EXPECT_TRUE(links.cameUp(d).empty());
    d.clear();
    appendLink(d, RTM_NEWLINK, 4, kRunning);
    EXPECT_EQ(links.cameUp(d), (std::vector<unsigned>{4}));
}

TEST(LinkStates, TruncatedAndMalformedDatagramsAreSkippedWithoutHarm) {
    LinkStates links({{2, false}});
    std::vector<std::uint8_t> d;
    appendLink(d, RTM_NEWLINK, 2, kRunning);
    // Cut in the middle of its ifinfomsg: its length says more than there is.
    std::vector<std::uint8_t> cut(d.begin(), d.begin() + NLMSG_HDRLEN + 4);
    EXPECT_TRUE(links.cameUp(cut).empty());
    // A length shorter than a header, and a datagram shorter than one.
    std::vector<std::uint8_t> bad = d;
    nlmsghdr header{};
    std::memcpy(&header, bad.data(), sizeof header);
    header.nlmsg_len = 4;
    std::memcpy(bad.data(), &header, sizeof header);
    EXPECT_TRUE(links.cameUp(bad).empty());
    EXPECT_TRUE(links.cameUp(std::vector<std::uint8_t>(3, 0xff)).empty());
    EXPECT_TRUE(links.cameUp({}).empty());
    // A message too short for an ifinfomsg says nothing about a link.
    std::vector<std::uint8_t> shortMessage(NLMSG_HDRLEN + 4, 0);
    header.nlmsg_len = static_cast<std::uint32_t>(shortMessage.size());
    header.nlmsg_type = RTM_NEWLINK;
    std::memcpy(shortMessage.data(), &header, sizeof header);
    EXPECT_TRUE(links.cameUp(shortMessage).empty());
    // The whole message still counts afterwards.
    EXPECT_EQ(links.cameUp(d), (std::vector<unsigned>{2}));
}

}  // namespace
}  // namespace skillcell::ua::mdns::link_states_test
