// SPDX-License-Identifier: MIT
// libFuzzer harness for the scene parser (issue 13): any bytes -> pd::pipeline::build_scene with
// a small node limit. A pd::Error (the tools' exit 2/3) is the expected answer to bad input;
// any other exception (a tool's exit 4), a sanitizer report or a hang is a finding.
#include "core/errors.hpp"
#include "core/log.hpp"
#include "pipeline/scene.hpp"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    static const pd::Log log("fuzz_scene", 0, pd::Verbosity::quiet);
    try {
        // 4000 nodes keeps one execution (meshing, bonds) in milliseconds.
        (void)pd::pipeline::build_scene(text, "fuzz_scene.json", log, 4000);
    } catch (const pd::Error&) {
        // exit 2 or 3 with a message: the right answer to bad input
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fuzz_scene: exception outside pd::Error (a tool's exit 4): %s\n",
                     e.what());
        std::abort();
    }
    return 0;
}
