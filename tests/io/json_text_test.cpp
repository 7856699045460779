// JSON text errors (io/json_text.h): a number too large for a double or malformed text is refused with the
// file, the line and the field path of the value at fault, in scripts and in lattice files alike, and never
// throws.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "io/script.h"
#include "io/json_text.h"
#include "io/lattice_json.h"
#include "io/script_json.h"

using namespace sculpt;

namespace {

// A script whose numbers are each a placeholder "@N" (so one can be replaced by an overflowing literal), with
// the field path of each, the line it is on, and its text.
struct Template {
    std::string text;
    std::vector<std::string> paths;
};

Template scriptTemplate() {
    Template t;
    t.text = R"({"ops": [
  {"op": "add_lattice", "name": "pie",
   "lattice": {"kind": "cylinder", "base": [@0, @1, @2], "axis": [0, 0, 1], "radius": @3, "height": @4, "chunks": [2, 6, 2]}},
  {"op": "drag", "steps": [[{"from": [@5, 0, 0], "to": [0, @6, 0]}]]}
]})";
    t.paths = {"ops[0].lattice.base[0]", "ops[0].lattice.base[1]", "ops[0].lattice.base[2]", "ops[0].lattice.radius",
               "ops[0].lattice.height", "ops[1].steps[0][0].from[0]", "ops[1].steps[0][0].to[1]"};
    return t;
}

std::string fill(const Template& t, int overflow, const std::string& literal) {
    std::string s = t.text;
    for (int n = static_cast<int>(t.paths.size()) - 1; n >= 0; --n) {
        const std::string key = "@" + std::to_string(n);
        const size_t at = s.find(key);
        s.replace(at, key.size(), n == overflow ? literal : "0.5");
    }
    return s;
}

}  // namespace

TEST_CASE("json text: an overflowing number names its file, line and field path", "[io]") {
    const Template t = scriptTemplate();
    for (int n = 0; n < static_cast<int>(t.paths.size()); ++n)
        for (const std::string literal : {"1e999", "-1e400", "2e308"}) {
            const std::string text = fill(t, n, literal);
            const int line = io::lineOfByte(text, text.find(literal));
            io::Script script;
            const Status s = io::parseScript(text, "edit.json", script);
            INFO(s.message);
            REQUIRE_FALSE(s);
            REQUIRE(s.message.rfind("edit.json:" + std::to_string(line) + ": " + t.paths[static_cast<size_t>(n)] + ": invalid JSON", 0) == 0);
        }
    // The same text with plain numbers is well-formed JSON.
    nlohmann::json plain;
    REQUIRE(io::parseJsonText(fill(t, -1, ""), "edit.json", plain));
    REQUIRE(plain["ops"][0]["lattice"]["radius"] == 0.5);
}

TEST_CASE("json text: malformed text names the line, and lattice files never throw", "[io]") {
    nlohmann::json out = 7;
    const Status s = io::parseJsonText("{\"a\": [1, 2,\n  3,, 4]}", "x.json", out);
    REQUIRE_FALSE(s);
    REQUIRE(s.message.rfind("x.json:2: a[3]: invalid JSON", 0) == 0);
    REQUIRE(out == 7);  // untouched
    // A lattice file with an overflowing radius: refused with its path, not an exception.
    const std::string file = R"({"format": "dmffd-lattice", "version": 1,
 "lattice": {"kind": "cylinder", "base": [0,0,0], "axis": [0,0,1], "radius": 1e999, "height": 1, "chunks": [1,4,1]}})";
    io::LatticeFile lattice;
    Status read;
    REQUIRE_NOTHROW(read = io::parseLatticeFile(file, "pie.lattice.json", lattice));
    INFO(read.message);
    REQUIRE_FALSE(read);
    REQUIRE(read.message.rfind("pie.lattice.json:2: lattice.radius: invalid JSON", 0) == 0);
    REQUIRE_FALSE(lattice.volume);
}
