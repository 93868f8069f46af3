#include "common/lcm/lcm_connection.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/dataset/dataset_test_util.h"

namespace hs {
namespace {

using ::testing::HasSubstr;

TEST(LcmConnection, MemqWorksAndBadUrlIsAnInputError) {
  EXPECT_TRUE(connect_lcm("memq://")->good());
  EXPECT_THAT(test::input_error_of([] { connect_lcm("nosuchprovider://x"); }),
              HasSubstr("LCM URL 'nosuchprovider://x'"));
}

TEST(LcmConnection, ReceiveBufferWarningFollowsRmemMax) {
  EXPECT_EQ(receive_buffer_warning("memq://"), "");
  const long long rmem_max = read_rmem_max();
  if (rmem_max <= 0) GTEST_SKIP() << "/proc/sys/net/core/rmem_max unreadable";
  const std::string base = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=";
  EXPECT_EQ(receive_buffer_warning(base + std::to_string(rmem_max)), "");
  EXPECT_THAT(receive_buffer_warning(base + std::to_string(rmem_max + 1)),
              HasSubstr("net.core.rmem_max is " + std::to_string(rmem_max)));
}

}  // namespace
}  // namespace hs
