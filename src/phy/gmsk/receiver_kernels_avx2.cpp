// Built with -mavx2 -ffp-contract=off (src/phy/gmsk/CMakeLists.txt).
#include "receiver_kernels_impl.hpp"

namespace rfsitl::phy::gmsk {

const ReceiverKernels& avx2_kernels() {
  static constexpr ReceiverKernels kKernels = kernels_of<8>("avx2");
  return kKernels;
}

}  // namespace rfsitl::phy::gmsk
