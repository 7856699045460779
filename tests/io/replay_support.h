// Shared by the recording tests: a recording written as JSON text, read back and replayed on a fresh session.
#pragma once

#include <catch2/catch.hpp>

#include "io/script.h"
#include "core/session/session.h"
#include "io/script_json.h"

namespace sculpt::test {

// recording -> scriptToJson -> parseScript -> runScript on (positions, triangles). `parsed` gets the script read back.
inline core::Session replayThroughJson(const io::Script& recording, const Positions& positions, const Triangles& triangles,
                                       io::Script& parsed) {
    const Status read = io::parseScript(io::scriptToJson(recording), "recording.json", parsed);
    INFO(read.message);
    REQUIRE(read.ok);
    core::Session replayed;
    REQUIRE(replayed.setMesh(positions, triangles, parsed.lattice).ok);
    replayed.setInjectivity(parsed.injectivity);
    io::ScriptReport report;
    const Status ran = io::runScript(replayed, parsed, report);
    INFO(ran.message);
    REQUIRE(ran.ok);
    return replayed;
}

}  // namespace sculpt::test
