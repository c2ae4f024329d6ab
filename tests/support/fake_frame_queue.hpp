#pragma once
/// A mac::FrameQueue test double: the frames a test lines up, every one ready.
#include <deque>
#include <utility>

#include "rfsitl/mac/mac.hpp"

namespace rfsitl::testing {

class FakeFrameQueue final : public mac::FrameQueue {
 public:
  const NetFrame* peek() override { return frames.empty() ? nullptr : &frames.front(); }
  NetFrame take() override {
    NetFrame f = std::move(frames.front());
    frames.pop_front();
    return f;
  }
  std::deque<NetFrame> frames;
};

}  // namespace rfsitl::testing
