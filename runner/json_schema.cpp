#include "runner/json_schema.h"

#include <cmath>

#include "runner/tolerance.h"

namespace hdrc {

using json = nlohmann::ordered_json;

namespace {

constexpr int kMaxDepth = 64;  // bounds $ref recursion
constexpr size_t kMaxErrors = 100;

class Validator {
 public:
  Validator(const json& root, std::string file, bool required)
      : root_(root), file_(std::move(file)), required_(required) {}

  void check(const json& v, const json& schema, const std::string& at, int depth) {
    if (errors.size() >= kMaxErrors) return;
    if (depth > kMaxDepth) return fail(at, "schema nesting deeper than 64", "");
    if (schema.is_boolean()) {
      if (!schema.get<bool>()) fail(at, "no value is allowed here, got " + brief(v), "");
      return;
    }
    if (!schema.is_object()) return fail(at, "the schema here is not an object", "");
    for (const char* unsupported : {"patternProperties", "if", "not", "dependentRequired",
                                    "dependentSchemas", "prefixItems", "contains", "pattern"})
      if (schema.contains(unsupported))
        return fail(at,
                    std::string("the schema uses \"") + unsupported +
                        "\", which this validator does not implement",
                    "");
    if (schema.contains("$ref")) {
      const std::string ref = schema["$ref"].get<std::string>();
      const std::string prefix = "#/$defs/";
      if (ref.rfind(prefix, 0) != 0 || !root_.contains("$defs") ||
          !root_["$defs"].contains(ref.substr(prefix.size())))
        return fail(at, "unresolvable $ref \"" + ref + "\"", "#/$defs/NAME");
      check(v, root_["$defs"][ref.substr(prefix.size())], at, depth + 1);
    }
    if (schema.contains("type") && !type_ok(v, schema["type"]))
      return fail(at, "expected " + schema["type"].dump() + ", got " + brief(v), "");
    if (schema.contains("const") && v != schema["const"])
      return fail(at, "expected " + schema["const"].dump() + ", got " + brief(v), "");
    if (schema.contains("enum")) {
      bool found = false;
      for (const auto& e : schema["enum"]) found = found || e == v;
      if (!found)
        return fail(at, "value " + brief(v) + " is not allowed", enum_list(schema["enum"]));
    }
    if (v.is_number()) {
      const double d = v.get<double>();
      if (schema.contains("minimum") && !(d >= schema["minimum"].get<double>()))
        fail(at, brief(v) + " is below the minimum " + schema["minimum"].dump(), "");
      if (schema.contains("maximum") && !(d <= schema["maximum"].get<double>()))
        fail(at, brief(v) + " is above the maximum " + schema["maximum"].dump(), "");
    }
    if (schema.contains("allOf"))  // every sub-schema, its errors as they are
      for (const auto& sub : schema["allOf"]) check(v, sub, at, depth + 1);
    for (const char* key : {"oneOf", "anyOf"}) {
      if (!schema.contains(key)) continue;
      size_t matched = 0;
      for (const auto& sub : schema[key]) {
        Validator probe(root_, file_, required_);
        probe.check(v, sub, at, depth + 1);
        matched += probe.errors.empty();
      }
      const bool one = std::string(key) == "oneOf";
      if (matched == 0 || (one && matched > 1))
        fail(at,
             brief(v) + (matched == 0 ? " matches none of the " : " matches several of the ") +
                 std::to_string(schema[key].size()) + " alternatives of " + key,
             "");
    }
    if (v.is_object()) check_object(v, schema, at, depth);
    if (v.is_array()) check_array(v, schema, at, depth);
  }

  std::vector<Error> errors;

 private:
  void check_object(const json& v, const json& schema, const std::string& at, int depth) {
    if (required_ && schema.contains("required"))
      for (const auto& k : schema["required"])
        if (!v.contains(k.get<std::string>()))
          fail(at + "/" + k.get<std::string>(),
               "missing required key \"" + k.get<std::string>() + "\"", "");
    const json* props = schema.contains("properties") ? &schema["properties"] : nullptr;
    for (auto it = v.begin(); it != v.end(); ++it) {
      const std::string child = at + "/" + escape_pointer_token(it.key());
      if (props && props->contains(it.key())) {
        check(it.value(), (*props)[it.key()], child, depth + 1);
      } else if (schema.contains("additionalProperties")) {
        const json& extra = schema["additionalProperties"];
        if (extra.is_boolean() && !extra.get<bool>())
          fail(child, "unknown key \"" + it.key() + "\"", props ? key_list(*props) : "");
        else
          check(it.value(), extra, child, depth + 1);
      }
    }
  }

  void check_array(const json& v, const json& schema, const std::string& at, int depth) {
    if (schema.contains("minItems") && v.size() < schema["minItems"].get<size_t>())
      fail(at,
           "expected at least " + schema["minItems"].dump() + " items, got " +
               std::to_string(v.size()),
           "");
    if (schema.contains("maxItems") && v.size() > schema["maxItems"].get<size_t>())
      fail(at,
           "expected at most " + schema["maxItems"].dump() + " items, got " +
               std::to_string(v.size()),
           "");
    if (schema.contains("items"))
      for (size_t i = 0; i < v.size() && errors.size() < kMaxErrors; ++i)
        check(v[i], schema["items"], at + "/" + std::to_string(i), depth + 1);
  }

  static bool type_is(const json& v, const std::string& t) {
    if (t == "object") return v.is_object();
    if (t == "array") return v.is_array();
    if (t == "string") return v.is_string();
    if (t == "boolean") return v.is_boolean();
    if (t == "null") return v.is_null();
    if (t == "number") return v.is_number();
    if (t == "integer")
      return v.is_number_integer() ||
             (v.is_number_float() && std::floor(v.get<double>()) == v.get<double>());
    return false;
  }
  static bool type_ok(const json& v, const json& type) {
    if (type.is_string()) return type_is(v, type.get<std::string>());
    for (const auto& t : type)
      if (type_is(v, t.get<std::string>())) return true;
    return false;
  }
  static std::string brief(const json& v) {
    std::string s = v.dump();
    return s.size() > 80 ? s.substr(0, 77) + "..." : s;
  }
  static std::string enum_list(const json& e) {
    std::string s;
    for (const auto& x : e) s += (s.empty() ? "" : ", ") + x.dump();
    return s;
  }
  static std::string key_list(const json& props) {
    std::string s;
    for (auto it = props.begin(); it != props.end(); ++it) s += (s.empty() ? "" : ", ") + it.key();
    return s;
  }
  void fail(const std::string& at, const std::string& message, const std::string& choices) {
    if (errors.size() < kMaxErrors) errors.push_back(Error{file_, at, message, choices});
  }

  const json& root_;
  std::string file_;
  bool required_;
};

}  // namespace

std::vector<Error> validate_json(const json& doc, const json& schema, const std::string& file,
                                 bool check_required) {
  Validator v(schema, file, check_required);
  v.check(doc, schema, "", 0);
  return v.errors;
}

}  // namespace hdrc
