// The JSON Schemas of results_schema/*.schema.json (embedded at build time)
// and a small checker for the subset of JSON Schema 2020-12 they use. There is
// no C++ JSON Schema validator in Debian 12, so this checks exactly these
// keywords: type (string or list), enum, const, required, properties,
// additionalProperties (bool or schema), items, minItems, minimum,
// exclusiveMinimum, maximum, minLength, pattern (ECMAScript) and local $ref
// ("#/$defs/name"); annotations ($schema, $id, $defs, title, description,
// $comment, default, examples) are ignored. Any other keyword is an error, so
// a schema is never "passed" by silently skipping a rule.
#ifndef BURRLAB_RESULTS_SCHEMA_SCHEMAS_H_
#define BURRLAB_RESULTS_SCHEMA_SCHEMAS_H_

#include <string_view>
#include <vector>

#include "burrlab/base/result.h"

namespace burrlab::results_schema {

// Names of the embedded schemas ("trial_record", "beh_sidecar",
// "physio_sidecar", "dataset_description", "session"), sorted.
std::vector<std::string_view> SchemaNames();

// Text of results_schema/<name>.schema.json; an error names the known schemas.
Result<std::string_view> SchemaText(std::string_view name);

// OK when JSON `instance` satisfies JSON Schema `schema` (the subset above);
// otherwise the first violation, e.g. "/GeneratedBy/0: missing required
// property \"Name\"".
Status CheckJson(std::string_view schema, std::string_view instance);

// CheckJson against the embedded schema `name`.
Status CheckJsonAgainst(std::string_view name, std::string_view instance);

}  // namespace burrlab::results_schema

#endif  // BURRLAB_RESULTS_SCHEMA_SCHEMAS_H_
