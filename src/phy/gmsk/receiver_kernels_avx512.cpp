// Built with -mavx512f -ffp-contract=off (src/phy/gmsk/CMakeLists.txt).
#include "receiver_kernels_impl.hpp"

namespace rfsitl::phy::gmsk {

const ReceiverKernels& avx512_kernels() {
  static constexpr ReceiverKernels kKernels = kernels_of<16>("avx512");
  return kKernels;
}

}  // namespace rfsitl::phy::gmsk
