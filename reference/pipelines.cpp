// The pipeline registry (core/pipeline.h). Adding a pipeline adds its module's line here.
#include <algorithm>
#include <string>

#include "core/pipeline.h"
#include "reference/operators/operators_pipeline.h"
#include "reference/pq_grading/pq_grading_pipeline.h"
#include "reference/ue/ue55/ue55_pipeline.h"
#include "reference/ue/ue58/ue58_pipeline.h"
#include "reference/unity_urp/unity_urp_pipeline.h"

namespace hdrc {

const std::vector<const Pipeline*>& pipeline_table() {
  static const std::vector<const Pipeline*> table = {
      &ref::ue55_pipeline(),
      &ref::unity_urp::unity_urp_pipeline(),
      &ref::operators::operators_pipeline(),
      &ref::pq_grading::pq_grading_pipeline(),
      &ref::ue58::ue58_pipeline(),
  };
  return table;
}

const Pipeline* find_pipeline(std::string_view name) {
  for (const Pipeline* p : pipeline_table())
    if (p->name == name) return p;
  return nullptr;
}

const Pipeline& default_pipeline() {
  return *pipeline_table().front();
}

const Pipeline& pipeline_of(const StageInfo& stage) {
  const Pipeline* p = find_pipeline(stage.pipeline);
  return p ? *p : default_pipeline();
}

std::string pipeline_names() {
  std::string out;
  for (const Pipeline* p : pipeline_table())
    out += (out.empty() ? "" : ", ") + std::string(p->name);
  return out;
}

const StageInfo* find_stage(const Pipeline& pipeline, std::string_view name) {
  for (const StageInfo& s : pipeline.stages())
    if (s.name == name) return &s;
  return nullptr;
}

const StageInfo* find_stage(std::string_view name) {
  for (const Pipeline* p : pipeline_table())
    if (const StageInfo* s = find_stage(*p, name)) return s;
  return nullptr;
}

std::string stage_names(const Pipeline& pipeline) {
  std::string out;
  for (const StageInfo& s : pipeline.stages())
    out += (out.empty() ? "" : ", ") + std::string(s.name);
  return out;
}

std::string stage_names() {
  std::string out;
  for (const Pipeline* p : pipeline_table()) out += (out.empty() ? "" : ", ") + stage_names(*p);
  return out;
}

StageCost stage_cost(const StageInfo& stage) {
  for (const StageCost& c : pipeline_of(stage).stage_costs)
    if (c.stage == stage.name) return c;
  StageCost dearest{stage.name};
  for (const Pipeline* p : pipeline_table())
    for (const StageCost& c : p->stage_costs) {
      dearest.us = std::max(dearest.us, c.us);
      dearest.us_per_pixel = std::max(dearest.us_per_pixel, c.us_per_pixel);
      dearest.us_per_lut_texel = std::max(dearest.us_per_lut_texel, c.us_per_lut_texel);
    }
  return dearest;
}

OutputEncoding output_encoding(const StageInfo& stage, const ParamBlock& p) {
  return pipeline_of(stage).output_encoding(stage, p);
}

}  // namespace hdrc
