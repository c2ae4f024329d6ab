// `ports.bind` / `--bind`: literals pass through, names resolve, failures name the value.
#include "rfsitl/io/bind_address.hpp"

#include <gtest/gtest.h>

#include <string>

namespace rfsitl::io {
namespace {

TEST(BindAddress, LiteralsAreKept) {
  EXPECT_EQ(resolve_bind_address("127.0.0.1"), "127.0.0.1");
  EXPECT_EQ(resolve_bind_address("0.0.0.0"), "0.0.0.0");
  EXPECT_EQ(resolve_bind_address("::1"), "::1");
}

TEST(BindAddress, LocalhostResolvesToLoopback) {
  EXPECT_EQ(resolve_bind_address("localhost"), "127.0.0.1");
}

TEST(BindAddress, UnresolvableNameIsAnErrorNamingIt) {
  try {
    resolve_bind_address("no-such-host.invalid");
    ADD_FAILURE() << "resolved";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'no-such-host.invalid': cannot resolve"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rfsitl::io
