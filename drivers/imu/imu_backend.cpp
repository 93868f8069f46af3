#include "drivers/imu/imu_backend.h"

#include "drivers/imu/iio_backend.h"
#include "drivers/imu/xsens_backend.h"

namespace hs {

std::unique_ptr<ImuBackend> make_imu_backend(const ImuDriverOptions& options) {
  if (options.backend == "iio") return std::make_unique<IioBackend>(options.iio);
  return std::make_unique<XsensBackend>(options);
}

}  // namespace hs
