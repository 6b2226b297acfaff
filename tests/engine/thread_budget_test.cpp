// The thread count under an address-space limit (engine/thread_budget.h): without a limit the
// request stands; with one, the threads' stacks take at most a quarter of the room left, and a
// larger request falls back with a warning that names it.
#include "engine/thread_budget.h"

#include <catch2/catch.hpp>

using namespace rayproc;

TEST_CASE("Thread budget: the request stands without a limit and falls back under a tight one",
          "[engine]") {
    const std::uint64_t MiB = std::uint64_t(1) << 20;
    SECTION("no limit") {
        ThreadBudget b = budgetThreads(1024, 64, 0);
        CHECK(b.threads == 1024);
        CHECK(b.mallocArenas == 0);
        CHECK(b.warning.empty());
        CHECK(budgetThreads(0, 64, 0).threads == 0); // all cores, as TBB decides
    }
    SECTION("a request that fits") {
        ThreadBudget b = budgetThreads(8, 64, 1000 * MiB);
        CHECK(b.threads == 8);
        CHECK(b.warning.empty());
        CHECK(b.mallocArenas == 3); // 250 MiB / 64 MiB
    }
    SECTION("1024 threads in 750 MiB of room") {
        ThreadBudget b = budgetThreads(1024, 64, 750 * MiB);
        CHECK(b.threads == int((750 * MiB / 4) / kThreadReserveBytes));
        CHECK(b.threads * kThreadReserveBytes <= 750 * MiB / 4);
        CHECK_THAT(b.warning, Catch::Contains("--threads 1024") &&
                                  Catch::Contains("address-space limit") &&
                                  Catch::Contains("using " + std::to_string(b.threads)));
    }
    SECTION("all cores when they do not fit") {
        ThreadBudget b = budgetThreads(0, 256, 400 * MiB);
        CHECK(b.threads == int((400 * MiB / 4) / kThreadReserveBytes));
        CHECK_THAT(b.warning, Catch::Contains("256 threads (all cores)"));
    }
    SECTION("at least one thread however little room is left") {
        ThreadBudget b = budgetThreads(4, 4, 1 * MiB);
        CHECK(b.threads == 1);
        CHECK(b.mallocArenas == 1);
        CHECK_FALSE(b.warning.empty());
    }
}
