// SPDX-License-Identifier: MIT
// The library's solve() refuses what the CLI refuses: changes of walls or loading (`sets`,
// pd-solve's `--restart --set`) without a restart used to be ignored silently, so a script
// calling the library ran the scene unchanged (issue 28).
#include "core/errors.hpp"
#include "pipeline/solve.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

TEST(SolveOptions, ChangesWithoutARestartAreRefusedBeforeTheFileIsOpened) {
    pd::pipeline::SolveOptions opt;
    opt.file = "no-such-file-solve-options.h5"; // refused before it is looked for
    opt.sets = {"walls.plate.velocity=[0,-1]"};
    pd::Context ctx{pd::Log("test", 0, pd::Verbosity::quiet), {}, 0, 1, {}};
    try {
        pd::pipeline::solve(opt, ctx);
        FAIL() << "solve() ran with sets and no restart";
    } catch (const pd::InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("walls.plate.velocity"), std::string::npos) << what;
        EXPECT_NE(what.find("restart"), std::string::npos) << what;
    }
    EXPECT_FALSE(std::filesystem::exists(opt.file));
}
