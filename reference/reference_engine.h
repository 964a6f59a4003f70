// The reference engine: UE 5.5's pipeline in double precision, evaluated pixel by pixel.
#pragma once

#include "core/engine.h"

namespace hdrc::ref {

class ReferenceEngine final : public Engine {
 public:
  std::string name() const override { return "reference"; }
  Status init() override { return {}; }
  DeviceInfo device() const override;
  Result<Image> run(const ResolvedCase& c) override;
};

// One pixel of a stage, for tests and `probe`: rgb in, rgb out.
Vec3 run_pixel(StageId stage, const ParamBlock& p, const Vec3& rgb);

}  // namespace hdrc::ref
