// The 64-bucket luminance histogram as UE 5.5 builds and reads it (reference:
// reference/ue/visualize/histogram.cpp):
//  * Histogram.usf: CalculateBucketsAndWeights, PackFloatToUINT32 (r.Histogram.UseAtomic = 1;
//    chenyong2github/UnrealEngine UE5 copy, commit 3961015d) — the bilinear splat between the two
//    buckets that straddle the position, each weight stored as 13.19 fixed point;
//  * PostProcessHistogramCommon.ush: ComputeAverageLuminanceWithoutOutlier (5.5, commit 2ad5a489);
//  * PostProcessVisualizeHDR.usf: ComputePlaceInHistogram (5.5, commit 39bb2572).
#ifndef HDRC_VISUALIZE_HISTOGRAM_GLSL
#define HDRC_VISUALIZE_HISTOGRAM_GLSL

#include "d3d_math.glsl"
#include "visualize_eye_adaptation.glsl"

const int HISTOGRAM_SIZE = 64;                       // HISTOGRAM_SIZE
const float HISTOGRAM_FIXED_POINT_ONE = 524288.0;    // PackFloatToUINT32: 1 << 19
const float HISTOGRAM_CONVERT_SCALE = 0.5;           // HistogramConvertCS's bilinear halving
const float HISTOGRAM_MIN_OUTLIER_WEIGHT = 0.0001;   // ComputeAverageLuminanceWithoutOutlier

// CalculateBucketsAndWeights for a pixel's pre-exposure-corrected colour: position
// f = saturate(pos(L)) · 63, buckets b0 = floor(f), b1 = min(b0 + 1, 63), weights 1 − frac(f) and
// frac(f) (the first scaled by BlackHistogramBucketInfluence when b0 = 0), packed as
// trunc(w · 2^19).
void histogram_splat(vec3 rgb, out int b0, out uint w0, out int b1, out uint w1) {
  float luminance = eye_adaptation_luminance(rgb);
  float f = saturate_d3d(histogram_position_from_luminance(luminance)) * float(HISTOGRAM_SIZE - 1);
  b0 = min(int(f), HISTOGRAM_SIZE - 1);
  b1 = min(b0 + 1, HISTOGRAM_SIZE - 1);
  float frac1 = f - floor(f);
  float frac0 = 1.0 - frac1;
  if (b0 == 0) frac0 *= EA_BLACK_HISTOGRAM_BUCKET_INFLUENCE;
  w0 = uint(frac0 * HISTOGRAM_FIXED_POINT_ONE);
  w1 = uint(frac1 * HISTOGRAM_FIXED_POINT_ONE);
}

// HistogramConvertCS: the exact 64-bit fixed-point sum (hi · 2^32 + lo) → Unpack (· 2^−19) · 0.5
// · InvViewSize.x · InvViewSize.y.
float histogram_bucket_value(uint hi, uint lo, int width, int height) {
  float fixed_sum = float(hi) * 4294967296.0 + float(lo);
  return fixed_sum / HISTOGRAM_FIXED_POINT_ONE * HISTOGRAM_CONVERT_SCALE *
         ((1.0 / float(width)) * (1.0 / float(height)));
}

// Bucket i is centred on position i / 63.
float histogram_bucket_centre_position(int bucket) {
  return float(bucket) / float(HISTOGRAM_SIZE - 1);
}

float histogram_sum(float h[HISTOGRAM_SIZE]) {
  float sum = 0.0;
  for (int i = 0; i < HISTOGRAM_SIZE; ++i) sum += h[i];
  return sum;
}

// ComputeHistogramMax: HLSL max (maxNum) from 0.
float histogram_max(float h[HISTOGRAM_SIZE]) {
  float m = 0.0;
  for (int i = 0; i < HISTOGRAM_SIZE; ++i) m = max_d3d(m, h[i]);
  return m;
}

// ComputeAverageLuminanceWithoutOutlier(h, sum · Low, sum · High): exp2 of the weighted mean log
// luminance at the bucket centres after dropping the lowest Low and everything above High of the
// total weight. min is HLSL's (minNum).
float average_luminance_without_outliers(float h[HISTOGRAM_SIZE]) {
  float sum = histogram_sum(h);
  float min_fraction = sum * EA_EXPOSURE_LOW_PERCENT;
  float max_fraction = sum * EA_EXPOSURE_HIGH_PERCENT;
  float weighted_log = 0.0;
  float weight = 0.0;
  for (int i = 0; i < HISTOGRAM_SIZE; ++i) {
    float value = h[i];
    float sub = min_d3d(value, min_fraction);
    value -= sub;
    min_fraction -= sub;
    max_fraction -= sub;
    value = min_d3d(value, max_fraction);
    max_fraction -= value;
    weighted_log +=
        log_luminance_from_histogram_position(histogram_bucket_centre_position(i)) * value;
    weight += value;
  }
  return exp2(weighted_log / max_d3d(HISTOGRAM_MIN_OUTLIER_WEIGHT, weight));
}

// ComputePlaceInHistogram: the fraction of histogram weight below the pixel. logL = log2(dot(rgb,
// 1) / 3) without the LuminanceMin clamp; bucket i counts fully when logL ≥ the log luminance of
// position (i+1)/63, linearly from that of i/63. NaN logL → saturate(NaN) = 0 per bucket; an empty
// histogram → 0/0 = NaN (as on D3D).
float place_in_histogram(vec3 rgb, float h[HISTOGRAM_SIZE]) {
  float log_luminance = log2_d3d(dot(rgb, vec3(1.0)) / 3.0);
  float sum_total = 0.0;
  float sum_below = 0.0;
  for (int i = 0; i < HISTOGRAM_SIZE; ++i) {
    float lo = log_luminance_from_histogram_position(histogram_bucket_centre_position(i));
    float hi = log_luminance_from_histogram_position(histogram_bucket_centre_position(i + 1));
    sum_below += h[i] * saturate_d3d((log_luminance - lo) / (hi - lo));
    sum_total += h[i];
  }
  return sum_below / sum_total;
}

#endif
