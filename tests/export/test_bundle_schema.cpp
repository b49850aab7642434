// The JSON Schemas in docs/ against what the engine writes: the bundle manifest and graph.json
// of exported bundles, the sample projects and their re-saved form. No JSON-Schema validator
// for C++ is packaged in Debian, so a small structural one lives here: it walks the schema and
// checks $ref, type, const, enum, required, properties, additionalProperties, items, oneOf,
// anyOf, not, min/maxItems, minLength, pattern and the numeric bounds (not if/then, formats or
// unevaluated*). Negative controls prove it can fail.
#include "test_support.h"

#include "plimsoll/export/bundle.h"
#include "plimsoll/project/project.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <regex>

namespace plimsoll {
namespace test_bundle_schema {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::readFile;

class SchemaChecker {
public:
    explicit SchemaChecker(json root) : root_(std::move(root)) {}

    /// Problems of `value` against the whole schema, one "path: problem" each.
    std::vector<std::string> check(const json& value) {
        problems_.clear();
        visit(root_, value, "$");
        return problems_;
    }

private:
    const json& resolve(const json& schema) const {
        const std::string ref = schema.at("$ref").get<std::string>();
        const std::string prefix = "#/$defs/";
        if (ref.rfind(prefix, 0) != 0) throw std::runtime_error("unsupported $ref " + ref);
        return root_.at("$defs").at(ref.substr(prefix.size()));
    }

    static bool hasType(const json& v, const std::string& type) {
        if (type == "object") return v.is_object();
        if (type == "array") return v.is_array();
        if (type == "string") return v.is_string();
        if (type == "boolean") return v.is_boolean();
        if (type == "null") return v.is_null();
        if (type == "number") return v.is_number();
        if (type == "integer")
            return v.is_number_integer() ||
                   (v.is_number_float() &&
                    v.get<double>() ==
                        static_cast<double>(static_cast<long long>(v.get<double>())));
        throw std::runtime_error("unknown type " + type);
    }

    bool matches(const json& schema, const json& value) {
        std::vector<std::string> saved;
        saved.swap(problems_);
        visit(schema, value, "");
        const bool ok = problems_.empty();
        problems_.swap(saved);
        return ok;
    }

    void fail(const std::string& path, const std::string& what) {
        problems_.push_back(path + ": " + what);
    }

    void visit(const json& schema, const json& v, const std::string& path) {
        if (schema.is_boolean()) {
            if (!schema.get<bool>()) fail(path, "not allowed");
            return;
        }
        if (schema.contains("$ref")) visit(resolve(schema), v, path);
        if (schema.contains("type")) {
            const json& t = schema["type"];
            bool any = false;
            if (t.is_string()) any = hasType(v, t.get<std::string>());
            for (const json& one : t.is_array() ? t : json::array())
                any = any || hasType(v, one.get<std::string>());
            if (!any)
                return fail(path,
                            "is " + std::string(v.type_name()) + ", the schema wants " + t.dump());
        }
        if (schema.contains("const") && v != schema["const"])
            fail(path, "is " + v.dump() + ", not " + schema["const"].dump());
        if (schema.contains("enum")) {
            const json& e = schema["enum"];
            if (std::find(e.begin(), e.end(), v) == e.end())
                fail(path, v.dump() + " is not one of " + e.dump());
        }
        if (v.is_number()) {
            const double x = v.get<double>();
            if (schema.contains("minimum") && x < schema["minimum"].get<double>())
                fail(path, "below minimum");
            if (schema.contains("maximum") && x > schema["maximum"].get<double>())
                fail(path, "above maximum");
            if (schema.contains("exclusiveMinimum") &&
                x <= schema["exclusiveMinimum"].get<double>())
                fail(path, "not above exclusiveMinimum");
        }
        if (v.is_string()) {
            const std::string s = v.get<std::string>();
            if (schema.contains("minLength") && s.size() < schema["minLength"].get<std::size_t>())
                fail(path, "too short");
            if (schema.contains("pattern") &&
                !std::regex_search(s, std::regex(schema["pattern"].get<std::string>())))
                fail(path, "does not match " + schema["pattern"].dump());
        }
        if (v.is_object()) {
            for (const json& key : schema.value("required", json::array()))
                if (!v.contains(key.get<std::string>()))
                    fail(path, "required key " + key.dump() + " missing");
            const json properties = schema.value("properties", json::object());
            for (const auto& [key, item] : v.items()) {
                if (properties.contains(key)) {
                    visit(properties[key], item, path + "." + key);
                } else if (schema.contains("additionalProperties")) {
                    const json& extra = schema["additionalProperties"];
                    if (extra.is_boolean() && !extra.get<bool>())
                        fail(path, "key \"" + key + "\" is not in the schema");
                    else if (extra.is_object())
                        visit(extra, item, path + "." + key);
                }
            }
        }
        if (v.is_array()) {
            if (schema.contains("minItems") && v.size() < schema["minItems"].get<std::size_t>())
                fail(path, "too few items");
            if (schema.contains("maxItems") && v.size() > schema["maxItems"].get<std::size_t>())
                fail(path, "too many items");
            if (schema.contains("items"))
                for (std::size_t i = 0; i < v.size(); ++i)
                    visit(schema["items"], v[i], path + "[" + std::to_string(i) + "]");
        }
        if (schema.contains("oneOf")) {
            int count = 0;
            for (const json& s : schema["oneOf"]) count += matches(s, v);
            if (count != 1)
                fail(path, "matches " + std::to_string(count) + " of oneOf's schemas, not 1");
        }
        if (schema.contains("anyOf")) {
            bool any = false;
            for (const json& s : schema["anyOf"]) any = any || matches(s, v);
            if (!any) fail(path, "matches none of anyOf's schemas");
        }
        if (schema.contains("not") && matches(schema["not"], v))
            fail(path, "matches a \"not\" schema");
    }

    json root_;
    std::vector<std::string> problems_;
};

json docSchema(const std::string& name) {
    return json::parse(readFile(fs::path(PLIMSOLL_SOURCE_DIR) / "docs" / name));
}

std::string joined(const std::vector<std::string>& lines) {
    std::string out;
    for (const std::string& l : lines) out += l + "\n";
    return out;
}

/// Exports body 0 of a sample project into a scratch folder.
fs::path exportSample(const std::string& stem) {
    Result<Project> project =
        loadProject(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / (stem + ".plim.json"));
    EXPECT_TRUE(project.ok()) << project.error().message;
    const fs::path folder = test::scratchFolder("bundle_schema") / stem;
    Result<BundleReport> report = writeBodyBundle(*project, 0, folder);
    EXPECT_TRUE(report.ok()) << report.error().message;
    return folder;
}

TEST(BundleSchema, ExportedManifestsAndGraphsFollowTheirSchemas) {
    SchemaChecker manifestSchema(docSchema("bundle-manifest.schema.json"));
    SchemaChecker graphSchema(docSchema("graph.schema.json"));
    for (const std::string stem : {"damaged_boat", "buoy", "box_half_draft"}) {
        SCOPED_TRACE(stem);
        const fs::path folder = exportSample(stem);
        const json manifest = json::parse(readFile(folder / "manifest.json"));
        EXPECT_EQ(joined(manifestSchema.check(manifest)), "");
        if (manifest["water_graph"].is_object()) {
            const json graph =
                json::parse(readFile(folder / manifest["water_graph"]["path"].get<std::string>()));
            EXPECT_EQ(joined(graphSchema.check(graph)), "");
            // The sample graph as written by hand follows it too.
        }

        // Negative controls: the checker notices a missing required key, a wrong type, a
        // path leaving the bundle and a newer major.
        json spoiled = manifest;
        spoiled.erase("files");
        EXPECT_NE(joined(manifestSchema.check(spoiled)).find("\"files\" missing"),
                  std::string::npos);
        spoiled = manifest;
        spoiled["texture_size"] = "128";
        EXPECT_NE(joined(manifestSchema.check(spoiled)).find("$.texture_size: is string"),
                  std::string::npos);
        spoiled = manifest;
        spoiled["files"][0]["path"] = "../x";
        EXPECT_FALSE(manifestSchema.check(spoiled).empty());
        spoiled = manifest;
        spoiled["schema_version"] = 2;
        EXPECT_FALSE(manifestSchema.check(spoiled).empty());
    }
    for (const char* file : {"boat.graph.json", "plush.graph.json"}) {
        const json graph = json::parse(readFile(fs::path(PLIMSOLL_SOURCE_DIR) / "projects" / file));
        EXPECT_EQ(joined(graphSchema.check(graph)), "") << file;
        json spoiled = graph;
        spoiled["nodes"][0].erase("capacity");
        EXPECT_NE(joined(graphSchema.check(spoiled)).find("$.nodes[0]: required key \"capacity\""),
                  std::string::npos);
        spoiled = graph;
        spoiled["pipes"][0]["open"] = 1;
        EXPECT_FALSE(graphSchema.check(spoiled).empty()) << file;
    }
}

// docs/gltf-physics.schema.json: the glTF node's extensions of exported bundles (one with
// exact mass properties, one painted shell without) follow it; a negative inertia moment, a
// missing OMI motion type and a bundle file leaving the folder do not.
TEST(BundleSchema, ExportedGltfNodeExtensionsFollowTheirSchema) {
    SchemaChecker schema(docSchema("gltf-physics.schema.json"));
    for (const std::string stem : {"box_half_draft", "buoy"}) {
        SCOPED_TRACE(stem);
        const fs::path folder = exportSample(stem);
        const json manifest = json::parse(readFile(folder / "manifest.json"));
        const json gltf = json::parse(readFile(folder / manifest.at("gltf").get<std::string>()));
        const json& extensions = gltf.at("nodes").at(0).at("extensions");
        EXPECT_EQ(joined(schema.check(extensions)), "");

        json spoiled = extensions;
        spoiled["KHR_physics_rigid_bodies"]["motion"]["inertiaDiagonal"][0] = -1.0;
        EXPECT_FALSE(schema.check(spoiled).empty());
        spoiled = extensions;
        spoiled["OMI_physics_body"]["motion"].erase("type");
        EXPECT_NE(joined(schema.check(spoiled)).find("required key \"type\""), std::string::npos);
        spoiled = extensions;
        spoiled["PLIMSOLL_buoyancy_bundle"]["files"].push_back("../elsewhere.exr");
        EXPECT_FALSE(schema.check(spoiled).empty());
    }
}

// docs/project.schema.json is current: every sample project, and what saveProject writes for
// it (every key the engine knows), follows it; it refuses keys it does not list.
TEST(BundleSchema, SampleProjectsAndSavedProjectsFollowTheProjectSchema) {
    SchemaChecker schema(docSchema("project.schema.json"));
    std::size_t checked = 0;
    for (const auto& entry : fs::directory_iterator(fs::path(PLIMSOLL_SOURCE_DIR) / "projects")) {
        const std::string name = entry.path().filename().string();
        if (name.size() < 10 || name.substr(name.size() - 10) != ".plim.json") continue;
        SCOPED_TRACE(name);
        const json original = json::parse(readFile(entry.path()));
        EXPECT_EQ(joined(schema.check(original)), "");
        Result<Project> project = loadProject(entry.path());
        ASSERT_TRUE(project.ok()) << project.error().message;
        EXPECT_EQ(joined(schema.check(json::parse(projectToJson(*project)))), "");
        ++checked;
        json spoiled = original;
        spoiled["bodies"][0]["an_unknown_key"] = 1;
        EXPECT_NE(joined(schema.check(spoiled)).find("\"an_unknown_key\" is not in the schema"),
                  std::string::npos);
    }
    EXPECT_GE(checked, 5u);
}

}  // namespace
}  // namespace test_bundle_schema
}  // namespace plimsoll
