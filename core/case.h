// A conformance case after loading: what to run, with which cvars, on which input, judged how.
#pragma once

#include <string>

#include "core/cvars.h"
#include "core/image.h"
#include "core/settings.h"
#include "core/shader_interface.h"
#include "core/stage.h"

namespace hdrc {

// Diff thresholds of one case. A verdict fails when any metric exceeds its limit; every
// comparison is written so that NaN fails.
struct Tolerance {
  double linear_abs = 0.0;  // max |cand − ref| where |ref| < rel_floor (scene-linear units)
  double linear_rel = 0.0;  // max |cand − ref| / max(|ref|, rel_floor)
  double rel_floor = 0.0;   // floor of the relative error's denominator
  double pq_code10 = 0.0;   // max |PQ(cand nits) − PQ(ref nits)| in 10-bit code values
  std::string reason;       // why these numbers (measured error and its cause)
  std::string source;       // where they came from: "cases/x.json: /tolerance" or "default"
};

// Where a case's input image comes from.
struct InputSpec {
  std::string stimulus;  // a procedural stimulus name, or "" when `file` is set
  std::string file;      // an image under cases/ (resolved path), or ""
  int width = 0;
  int height = 0;
  std::string describe() const;
};

struct Case {
  std::string id;    // stable, readable: "linear_device/dev7_gamut2_log_ramp"
  std::string file;  // the case file it came from
  const StageInfo* stage = nullptr;
  CvarValues cvars;
  SettingValues settings;  // post-process and view settings (UE defaults when unset)
  InputSpec input;
  InputSpec bloom;       // tonemap: the bloom texture (stimulus "" and file "": no bloom)
  InputSpec bloom_dirt;  // tonemap: the bloom dirt mask texture (empty: none)
  Tolerance tolerance;
};

// A case with everything an engine needs: the host-derived parameters and the input pixels.
struct ResolvedCase {
  Case spec;
  ParamBlock params;
  Image input;
  Image ui;  // ui_composite: the UI layer (premultiplied, sRGB-encoded), same size as `input`
  Image bloom, bloom_dirt;  // tonemap: bloom and dirt mask textures (empty when not given)
  // Non-empty when UE computes degenerate parameters for this combination (e.g. an ACES device
  // while MaxLuminance resolves to 0): the case is reported as DEGENERATE, never evaluated as a
  // pass.
  std::string degenerate;
};

}  // namespace hdrc
