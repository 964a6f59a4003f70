// probe's fast parsing and printing (runner/probe.cpp) against the general path it replaces:
// every line printed as format_number (%.9g) of the reference's value, and the inputs the fast
// parser does not take handled exactly as before.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "reference/ue/tonemap.h"
#include "reference/ue/cpp/resolve.h"
#include "runner/probe.h"

namespace {

hdrc::ProbeOptions options() {
  hdrc::ProbeOptions o;
  o.set = {"r.HDR.EnableHDROutput=1", "r.HDR.Display.OutputDevice=3", "r.HDR.Display.ColorGamut=2"};
  return o;
}

std::string probe(const std::string& text, hdrc::Status* st = nullptr) {
  std::istringstream in(text);
  std::ostringstream out;
  hdrc::Status s = hdrc::run_probe(options(), in, out);
  if (st) *st = s;
  return out.str();
}

TEST(ProbeFast, PrintsFormatNumberOfTheReferenceValue) {
  hdrc::Case c;
  c.stage = hdrc::find_stage("tonemap");
  c.cvars.set("r.HDR.EnableHDROutput", 1);
  c.cvars.set("r.HDR.Display.OutputDevice", 3);
  c.cvars.set("r.HDR.Display.ColorGamut", 2);
  const hdrc::ParamBlock p = *hdrc::ref::resolve_params(c, 1, 1);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-7.0, 4.0);
  std::string text, want;
  char line[160];
  for (int i = 0; i < 2000; ++i) {
    double v[3];
    for (double& x : v) x = std::pow(10.0, u(rng)) * (i % 13 == 0 ? -1.0 : 1.0);
    std::snprintf(line, sizeof line, "%.17g\t%.17g  %.17g\r\n", v[0], v[1], v[2]);
    text += line;
    const auto o = hdrc::ref::tonemap_centre_pixel(p, {v[0], v[1], v[2]}, nullptr);
    want += hdrc::format_number(o[0]) + " " + hdrc::format_number(o[1]) + " " +
            hdrc::format_number(o[2]) + "\n";
  }
  text += "nan inf -inf\n";
  const auto o = hdrc::ref::tonemap_centre_pixel(p, {std::nan(""), INFINITY, -INFINITY}, nullptr);
  want += hdrc::format_number(o[0]) + " " + hdrc::format_number(o[1]) + " " +
          hdrc::format_number(o[2]) + "\n";
  EXPECT_EQ(probe(text), want);
}

TEST(ProbeFast, InputsTheFastParserLeavesBehaveAsBefore) {
  // A leading '+' (std::stod takes it, std::from_chars does not): the same value.
  EXPECT_EQ(probe("+0.18 +0.18 +0.18\n"), probe("0.18 0.18 0.18\n"));
  // A value that underflows to a subnormal, or overflows, is rejected as std::stod rejects it.
  for (const char* bad : {"1e-310 2 3\n", "1e400 2 3\n", "1 2\n", "1 2 3 4\n", "1 2 x\n"}) {
    hdrc::Status st;
    probe(bad, &st);
    EXPECT_FALSE(st.ok()) << bad;
  }
  // Lines before a bad line are printed.
  hdrc::Status st;
  EXPECT_EQ(probe("0.18 0.18 0.18\nbad\n", &st), probe("0.18 0.18 0.18\n"));
  EXPECT_FALSE(st.ok());
}

}  // namespace
