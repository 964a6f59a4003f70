// junit.xml against what the common JUnit schemas require of a <testsuite> (Ant's and Jenkins'
// junit-10.xsd, which GitLab's and GitHub's JUnit publishers follow): a `timestamp` (ISO 8601
// date and time, no time zone), a `hostname`, and `time` in seconds as a decimal (we write at
// most 3 decimals, as Ant and Maven Surefire do). The file is parsed by an XML parser (expat),
// not searched as text.
#include <expat.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "runner/results.h"
#include "runner/test_support.h"

namespace fs = std::filesystem;
using namespace hdrc::test;  // runner/test_support.h

namespace {

struct Element {
  std::string name;
  std::map<std::string, std::string> attributes;
};

// Every element of `xml` with its attributes, in document order; empty with a failure recorded
// when the XML is not well-formed.
std::vector<Element> parse_xml(const std::string& xml) {
  std::vector<Element> out;
  XML_Parser p = XML_ParserCreate("UTF-8");
  XML_SetUserData(p, &out);
  XML_SetStartElementHandler(p, [](void* data, const XML_Char* name, const XML_Char** atts) {
    Element e{name, {}};
    for (int i = 0; atts[i]; i += 2) e.attributes[atts[i]] = atts[i + 1];
    static_cast<std::vector<Element>*>(data)->push_back(std::move(e));
  });
  const bool ok = XML_Parse(p, xml.data(), static_cast<int>(xml.size()), 1) == XML_STATUS_OK;
  EXPECT_TRUE(ok) << XML_ErrorString(XML_GetErrorCode(p)) << " at line "
                  << XML_GetCurrentLineNumber(p);
  XML_ParserFree(p);
  if (!ok) out.clear();
  return out;
}

std::vector<Element> named(const std::vector<Element>& all, const std::string& name) {
  std::vector<Element> out;
  for (const auto& e : all)
    if (e.name == name) out.push_back(e);
  return out;
}

// xs:dateTime as the schemas restrict it: no time zone, no fraction.
const std::regex kTimestamp("[0-9]{4}-[0-9]{2}-[0-9]{2}T[0-9]{2}:[0-9]{2}:[0-9]{2}");
// Seconds: a decimal with at most 3 decimals.
const std::regex kTime("[0-9]+(\\.[0-9]{1,3})?");

// Every time attribute is a decimal of at most 3 decimals; every <testsuite> has a timestamp
// and a hostname.
void expect_schema_attributes(const std::vector<Element>& all) {
  for (const auto& e : all) {
    if (auto t = e.attributes.find("time"); t != e.attributes.end()) {
      EXPECT_TRUE(std::regex_match(t->second, kTime)) << e.name << " time=" << t->second;
    }
  }
  const auto suites = named(all, "testsuite");
  ASSERT_FALSE(suites.empty());
  for (const auto& s : suites) {
    EXPECT_TRUE(s.attributes.count("time")) << s.attributes.at("name");
    EXPECT_TRUE(std::regex_match(s.attributes.at("timestamp"), kTimestamp))
        << s.attributes.at("timestamp");
    EXPECT_FALSE(s.attributes.at("hostname").empty());
  }
}

// A results document with known values: the attributes are those values, rounded as stated.
TEST(Junit, TimestampHostnameAndTimeFromTheResults) {
  nlohmann::ordered_json doc = {
      {"started_utc", "2026-01-02T03:04:05Z"},
      {"wall_seconds", 12.3456789},
      {"provenance", {{"hostname", "ci-runner-7"}}},
      {"cases",
       {{{"id", "a/b"}, {"stage", "shaper"}, {"verdict", "PASS"}, {"seconds", {{"total", 0.0004}}}},
        {{"id", "a/c"},
         {"stage", "shaper"},
         {"verdict", "FAIL"},
         {"reason", "worst pixel"},
         {"seconds", {{"total", 2.0004}}}}}},
      {"goldens",
       {{"seconds", 0.25},
        {"cases",
         {{{"id", "a/b"}, {"outcome", "match"}}, {{"id", "a/c"}, {"outcome", "regression"}}}}}}};
  const auto all = parse_xml(hdrc::junit_from_results(doc));
  expect_schema_attributes(all);
  const auto suites = named(all, "testsuite");
  ASSERT_EQ(suites.size(), 2u);
  for (const auto& s : suites) {
    EXPECT_EQ(s.attributes.at("timestamp"), "2026-01-02T03:04:05");  // UTC, the 'Z' dropped
    EXPECT_EQ(s.attributes.at("hostname"), "ci-runner-7");
  }
  EXPECT_EQ(suites[0].attributes.at("time"), "12.346");
  EXPECT_EQ(suites[1].attributes.at("time"), "0.250");
  const auto cases = named(all, "testcase");
  ASSERT_EQ(cases.size(), 4u);
  EXPECT_EQ(cases[0].attributes.at("time"), "0.000");
  EXPECT_EQ(cases[1].attributes.at("time"), "2.000");
  // The totals: 2 cases and 2 goldens, 1 failed case and 1 regressed golden.
  const auto top = named(all, "testsuites");
  ASSERT_EQ(top.size(), 1u);
  EXPECT_EQ(top[0].attributes.at("tests"), "4");
  EXPECT_EQ(top[0].attributes.at("failures"), "2");
  EXPECT_EQ(top[0].attributes.at("time"), "12.346");
}

// A real run's junit.xml: started when results.json says, on this host, for as long.
TEST(Junit, ARunsFileFollowsTheSchemas) {
  const fs::path out = temp_dir("junit");
  const Ran r =
      run("run --engine reference --filter 'tonemap/shaper_pq/dev3_*' --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.out;
  const auto doc = nlohmann::json::parse(read(out / "results.json"));
  const auto all = parse_xml(read(out / "junit.xml"));
  expect_schema_attributes(all);
  char host[256] = {0};
  ASSERT_EQ(gethostname(host, sizeof host - 1), 0);
  std::string started = doc["started_utc"].get<std::string>();
  started.pop_back();  // the 'Z'
  char wall[32];
  std::snprintf(wall, sizeof wall, "%.3f", doc["wall_seconds"].get<double>());
  const auto suites = named(all, "testsuite");
  ASSERT_EQ(suites.size(), 2u);  // the cases, the goldens
  for (const auto& s : suites) {
    EXPECT_EQ(s.attributes.at("timestamp"), started);
    EXPECT_EQ(s.attributes.at("hostname"), host);
  }
  EXPECT_EQ(suites[0].attributes.at("time"), wall);
  EXPECT_EQ(suites[0].attributes.at("tests"), std::to_string(doc["cases"].size()));
  fs::remove_all(out);
}

}  // namespace
