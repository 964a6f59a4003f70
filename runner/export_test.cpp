// The export format's parameter round trip (every ParamBlock field, non-finite values included)
// and the command-template splitting `verify --candidate-cmd` uses instead of a shell.
#include "runner/export.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "runner/verify.h"

namespace {

TEST(Export, ParamsRoundTripExactlyIncludingNonFinite) {
  hdrc::ParamBlock p;
  p.output_device = 3;
  p.output_max_luminance = 1000.0 / 3.0;  // not a short decimal
  p.aces_coefs_high_4 = std::numeric_limits<double>::quiet_NaN();
  p.aces_min_max = {0.1, -std::numeric_limits<double>::infinity(), 1e-300, 5};
  p.ap1_to_output(1, 2) = std::nextafter(0.25, 1.0);
  const auto j = hdrc::params_json(p);
  EXPECT_EQ(j["aces_coefs_high_4"], "NaN");
  EXPECT_EQ(j["aces_min_max"][1], "-Infinity");
  const auto back =
      hdrc::params_from_json(nlohmann::ordered_json::parse(j.dump()), "p.json", "/params");
  ASSERT_TRUE(back.ok()) << back.error().to_string();
  EXPECT_EQ(back->output_device, 3);
  EXPECT_EQ(back->output_max_luminance, p.output_max_luminance);
  EXPECT_TRUE(std::isnan(back->aces_coefs_high_4));
  EXPECT_EQ(back->aces_min_max, p.aces_min_max);
  EXPECT_EQ(back->ap1_to_output.m, p.ap1_to_output.m);
  // Byte for byte: every field survives (NaN compares unequal, so compare the bytes of a copy
  // with the NaN replaced on both sides).
  hdrc::ParamBlock a = p, b = *back;
  a.aces_coefs_high_4 = b.aces_coefs_high_4 = 0;
  EXPECT_EQ(hdrc::params_json(a).dump(), hdrc::params_json(b).dump());
}

TEST(Export, MissingOrBadParameterIsLocated) {
  auto j = hdrc::params_json(hdrc::ParamBlock{});
  j.erase("film_slope");
  auto r = hdrc::params_from_json(j, "p.json", "/params");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().to_string(),
            "p.json: /params/film_slope: missing parameter film_slope; valid choices: every "
            "ParamBlock field");
  j = hdrc::params_json(hdrc::ParamBlock{});
  j["wcs_to_ap1"][2] = {1, 2};
  r = hdrc::params_from_json(j, "p.json", "/params");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().pointer, "/params/wcs_to_ap1/2");
}

TEST(Verify, CommandTemplateSplitsLikeAShellWithoutOne) {
  auto w = hdrc::split_command_template(
      R"(my_port --in {input} 'a b' "c \"d\" \\" e\ f $HOME;rm `x` *)");
  ASSERT_TRUE(w.ok());
  const std::vector<std::string> want = {"my_port", "--in",     "{input}", "a b", "c \"d\" \\",
                                         "e f",     "$HOME;rm", "`x`",     "*"};
  EXPECT_EQ(*w, want);
  EXPECT_FALSE(hdrc::split_command_template("x 'open").ok());
  EXPECT_FALSE(hdrc::split_command_template("x \"open").ok());
  EXPECT_FALSE(hdrc::split_command_template("   ").ok());
  // Placeholders are replaced inside words after splitting: a value with spaces or shell
  // characters stays one argument.
  const auto argv = hdrc::expand_placeholders({"p", "--out={output}", "{id}"}, "in.exr", "p.json",
                                              "/o dir/$(x).exr", "a/b c");
  EXPECT_EQ(argv, (std::vector<std::string>{"p", "--out=/o dir/$(x).exr", "a/b c"}));
}

TEST(Verify, RunCommandReportsExitSignalAndTimeout) {
  const std::string log = ::testing::TempDir() + "/hdrc_cmd.log";
  auto r = hdrc::run_command({"sh", "-c", "echo hi; exit 7"}, log, 10);
  EXPECT_EQ(r.exit_status, 7);
  EXPECT_FALSE(r.timed_out);
  r = hdrc::run_command({"sh", "-c", "kill -TERM $$"}, log, 10);
  EXPECT_EQ(r.signal, 15);
  r = hdrc::run_command({"sleep", "20"}, log, 0.2);
  EXPECT_TRUE(r.timed_out);
  r = hdrc::run_command({"/nonexistent/program"}, log, 10);
  EXPECT_EQ(r.exit_status, 127);
}

}  // namespace
