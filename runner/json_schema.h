// A validator for the subset of JSON Schema (draft 2020-12) the project's schemas use:
// type (one or a list), enum, const, required, properties, additionalProperties (false or a
// schema), items, minItems, maxItems, minimum, maximum, oneOf, anyOf, allOf and
// "$ref": "#/$defs/NAME". Keywords outside the subset are ignored except those that change what is
// valid (patternProperties, if/then/else, $ref elsewhere): they are reported as errors of the
// schema, so a schema never silently claims more than is checked.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/result.h"

namespace hdrc {

// Every way `doc` breaks `schema`, as errors naming `file`, the JSON pointer into the document,
// the offending value and what the schema wants. Empty: valid. Without `check_required`, "required"
// is not checked: only the values present are (their types, values and keys), for a reader that
// gives a missing field its default.
std::vector<Error> validate_json(const nlohmann::ordered_json& doc,
                                 const nlohmann::ordered_json& schema, const std::string& file,
                                 bool check_required = true);

}  // namespace hdrc
