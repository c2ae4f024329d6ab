// The reference and the portable (SSE2) versions, and the choice at run time.
// Built with -ffp-contract=off (src/phy/gmsk/CMakeLists.txt).
#include <vector>

#include "receiver_kernels_impl.hpp"

namespace rfsitl::phy::gmsk {
namespace {

constexpr ReceiverKernels kReference = kernels_of<1>("reference");
constexpr ReceiverKernels kPortable = kernels_of<4>("portable");

/// The versions this CPU runs, slowest first. A plain list of function
/// pointers (not an ifunc), so that it works under the sanitizers too.
std::vector<const ReceiverKernels*> detect() {
  std::vector<const ReceiverKernels*> v{&kReference, &kPortable};
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) v.push_back(&avx2_kernels());
  if (__builtin_cpu_supports("avx512f")) v.push_back(&avx512_kernels());
  return v;
}

const std::vector<const ReceiverKernels*>& supported() {
  static const std::vector<const ReceiverKernels*> v = detect();
  return v;
}

}  // namespace

const ReceiverKernels& reference_kernels() {
  return kReference;
}

std::span<const ReceiverKernels* const> supported_kernels() {
  return supported();
}

const ReceiverKernels& fastest_kernels() {
  return *supported().back();
}

}  // namespace rfsitl::phy::gmsk
