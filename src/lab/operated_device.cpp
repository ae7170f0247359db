// The lab as one Device for a servo loop. See include/inhap/lab/operated_device.hpp.
#include "inhap/lab/operated_device.hpp"

namespace inhap::lab {

OperatedDevice::OperatedDevice(const Scene& scene, const RecordSpec& spec,
                               std::size_t reserve_ticks)
    : scene_(scene),
      spec_(spec),
      setup_(make_record_setup(scene_, spec_)),
      log_(*setup_.device, reserve_ticks) {
  setup_.op->begin(*setup_.device);  // as lab::record: logger first, then the hand takes over
}

void OperatedDevice::tick() {
  log_.sample();
  setup_.op->step(*setup_.device);
  setup_.device->tick();
}

LabRecording OperatedDevice::take_log() {
  LabRecording r = log_.take();
  r.comments = record_comments(scene_, spec_, setup_);
  return r;
}

}  // namespace inhap::lab
