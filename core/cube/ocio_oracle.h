// Test-only: OpenColorIO's FileTransform on a .cube file as the oracle the .cube tests compare
// with (core/cube/cube_test.cpp, reference/pq_grading/pq_grading_test.cpp). OpenColorIO reads both
// the Iridas and the Resolve flavour; a raw config with its processor cache off, so every file is
// read afresh.
#pragma once

#include <OpenColorIO/OpenColorIO.h>

#include <string>

namespace hdrc::cube::testing {

namespace OCIO = OCIO_NAMESPACE;

// The CPU processor of `path` with `interp` (INTERP_LINEAR: trilinear; INTERP_TETRAHEDRAL), no
// optimisation, forward.
inline OCIO::ConstCPUProcessorRcPtr ocio_processor(const std::string& path,
                                                   OCIO::Interpolation interp) {
  static const OCIO::ConfigRcPtr cfg = [] {
    OCIO::ConfigRcPtr c = OCIO::Config::CreateRaw()->createEditableCopy();
    c->setProcessorCacheFlags(OCIO::PROCESSOR_CACHE_OFF);
    return c;
  }();
  auto t = OCIO::FileTransform::Create();
  t->setSrc(path.c_str());
  t->setInterpolation(interp);
  t->setDirection(OCIO::TRANSFORM_DIR_FORWARD);
  return cfg->getProcessor(t)->getOptimizedCPUProcessor(OCIO::OPTIMIZATION_NONE);
}

}  // namespace hdrc::cube::testing
