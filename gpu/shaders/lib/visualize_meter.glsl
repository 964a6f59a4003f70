// VisualizeHDR's meters (PostProcessVisualizeHDR.usf: MainPS, 5.5 commit 39bb2572; docs/spec/ue55.md §9,
// docs/ue55-decisions.md D9, D-S2 item 5): the luminance meter averages 21×21 bilinear samples at
// UVViewportCenter + offset · ExtentInverse, the illuminance meter 16×16 samples (offsets −8..7)
// around (centre − (0, 100)) · ExtentInverse; the pass's sampler is bilinear with clamp
// addressing. Reference: reference/ue/visualize/visualize_hdr.cpp (sample_bilinear and the meters).
#ifndef HDRC_VISUALIZE_METER_GLSL
#define HDRC_VISUALIZE_METER_GLSL

const int METER_SAMPLES = 21;              // luminance meter: −10..10 in x and y
const int ILLUMINANCE_SAMPLES = 16;        // illuminance meter: −8..7 in x and y
const int ILLUMINANCE_OFFSET_Y = 100;      // OutputViewportCenter − uint2(0, 100)
const float VIS_PI = 3.14159265358979324;  // E = π · mean (LUX)
// Luminance() of Common.ush, the weights MainPS prints the meters with.
const vec3 UE_LUMINANCE_WEIGHTS = vec3(0.3, 0.59, 0.11);

// The four texels and weights of a bilinear sample with clamp addressing at texel-space
// coordinates (fx, fy) (texel i's centre at i, i.e. UV · extent − 0.5). The meters only sample at
// integer or half-integer coordinates, where every filter's weights (0, ½, 1) are exact; the taps
// are combined in buffer code (bilinear_combine) because GLSL cannot pass a buffer to a function.
struct BilinearTaps {
  int i00, i10, i01, i11;  // row-major pixel indices: (x0, y0), (x1, y0), (x0, y1), (x1, y1)
  float tx, ty;
};

BilinearTaps bilinear_taps(float fx, float fy, int width, int height) {
  float x0 = floor(fx);
  float y0 = floor(fy);
  BilinearTaps t;
  t.tx = fx - x0;
  t.ty = fy - y0;
  int xa = int(clamp(x0, 0.0, float(width - 1)));
  int xb = int(clamp(x0 + 1.0, 0.0, float(width - 1)));
  int ya = int(clamp(y0, 0.0, float(height - 1)));
  int yb = int(clamp(y0 + 1.0, 0.0, float(height - 1)));
  t.i00 = ya * width + xa;
  t.i10 = ya * width + xb;
  t.i01 = yb * width + xa;
  t.i11 = yb * width + xb;
  return t;
}

vec3 bilinear_combine(vec3 c00, vec3 c10, vec3 c01, vec3 c11, BilinearTaps t) {
  vec3 top = c00 * (1.0 - t.tx) + c10 * t.tx;
  vec3 bottom = c01 * (1.0 - t.tx) + c11 * t.tx;
  return top * (1.0 - t.ty) + bottom * t.ty;
}

// OutputViewportCenter = (int2)(ViewportMin + ViewportSize / 2).
ivec2 meter_centre(int width, int height) {
  return ivec2(int(float(width) * 0.5), int(float(height) * 0.5));
}

// Sample k (0 .. 440) of the luminance meter, texel-space coordinates.
vec2 meter_sample_position(int k, int width, int height) {
  int ox = k / METER_SAMPLES - METER_SAMPLES / 2;
  int oy = k % METER_SAMPLES - METER_SAMPLES / 2;
  return vec2(float(width) * 0.5 + float(ox) - 0.5, float(height) * 0.5 + float(oy) - 0.5);
}

// The illuminance meter's centre row: OutputViewportCenter.y − 100 as uint, which wraps when the
// centre is above row 100 (then every sample clamps to the bottom row and the meter's pixels lie
// outside the image).
float illuminance_centre_y(int centre_y) {
  return centre_y >= ILLUMINANCE_OFFSET_Y ? float(centre_y - ILLUMINANCE_OFFSET_Y)
                                          : float(centre_y) - float(ILLUMINANCE_OFFSET_Y) +
                                                4294967296.0;
}

// Sample k (0 .. 255) of the illuminance meter, texel-space coordinates.
vec2 illuminance_sample_position(int k, int width, int height) {
  ivec2 c = meter_centre(width, height);
  int ox = k / ILLUMINANCE_SAMPLES - ILLUMINANCE_SAMPLES / 2;
  int oy = k % ILLUMINANCE_SAMPLES - ILLUMINANCE_SAMPLES / 2;
  return vec2(float(c.x) + float(ox) - 0.5, illuminance_centre_y(c.y) + float(oy) - 0.5);
}

float ue_luminance(vec3 rgb) { return dot(rgb, UE_LUMINANCE_WEIGHTS); }

#endif
