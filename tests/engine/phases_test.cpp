// The phase log behind --stats' phases: entries add up by name in first-use order, a timer
// around nested timers keeps only its own time, a named loop is a parallel phase of its own, the
// summary's fractions follow the kinds.
#include "engine/phases.h"
#include "engine/stats.h"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

namespace rayproc {

TEST_CASE("A phase entered twice adds up, in the order phases first ran", "[engine]") {
    PhaseLog log;
    log.add("load", PhaseKind::Serial, 1.0);
    log.add("render", PhaseKind::Workers, 2.0, 3.0, 2);
    log.add("load", PhaseKind::Serial, 0.5);
    REQUIRE(log.phases().size() == 2);
    CHECK(log.phases()[0].name == "load");
    CHECK(log.phases()[0].seconds == 1.5);
    CHECK(log.phases()[0].count == 2);
    CHECK(log.phases()[1].busyFraction() == Approx(0.75)); // 3 thread-s of 2 s x 2 threads
    CHECK(log.phases()[0].busyFraction() < 0);             // serial: no busy figure
    CHECK(log.recordedSeconds() == 3.5);
}

TEST_CASE("A timer around nested timers records only its own time", "[engine]") {
    PhaseLog log;
    {
        PhaseTimer outer(&log, "outer");
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        log.add("inner", PhaseKind::Parallel, 10.0); // as if a nested phase took 10 s
    }
    REQUIRE(log.phases().size() == 2);
    // The outer phase lasted ~20 ms of which the nested phase claimed more: it keeps nothing
    // rather than a negative time, and no second is counted twice.
    CHECK(log.phases()[1].name == "outer");
    CHECK(log.phases()[1].seconds == 0);
    PhaseTimer stopped(&log, "twice");
    stopped.stop();
    stopped.stop();
    CHECK(log.phases().back().count == 1);
    PhaseTimer none(nullptr, "no log"); // records nothing, fails nothing
    none.stop();
    CHECK(log.phases().size() == 3);
}

TEST_CASE("A named loop is a parallel phase of the thread whose log is installed", "[engine]") {
    PhaseLog log;
    std::atomic<int> bodies{0};
    auto loop = [&] {
        tbb::parallel_for(0, 64, [&](int) { bodies.fetch_add(1); });
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    };
    namedLoop("unlogged", loop); // no log installed: nothing recorded
    CHECK(log.phases().empty());
    {
        LoopLog::Scope scope(&log);
        {
            PhaseTimer outer(&log, "load");
            namedLoop("decode", loop);
            namedLoop("decode", [&] { namedLoop("inner", loop); }); // nested: only the outer
        }
        std::thread other([&] { namedLoop("elsewhere", loop); }); // another thread: no log
        other.join();
    }
    namedLoop("after", loop); // the scope ended
    CHECK(bodies.load() == 5 * 64); // every loop ran, logged or not
    REQUIRE(log.phases().size() == 2);
    const PhaseStats& decode = log.phases()[0];
    CHECK(decode.name == "decode");
    CHECK(decode.kind == PhaseKind::Parallel);
    CHECK(decode.count == 2);
    CHECK(decode.seconds >= 0.010);
    // The serial phase around the loops keeps only its own time: none beyond them here.
    CHECK(log.phases()[1].name == "load");
    CHECK(log.phases()[1].seconds < decode.seconds);
    CHECK(log.recordedSeconds() == Approx(decode.seconds + log.phases()[1].seconds));
}

TEST_CASE("The summary's serial seconds and busy fraction", "[engine]") {
    std::vector<PhaseStats> phases{{"a", PhaseKind::Serial, 1.0, 0, 1, 1},
                                   {"b", PhaseKind::Parallel, 2.0, 0, 1, 1},
                                   {"c", PhaseKind::Workers, 3.0, 3.0, 2, 1},
                                   {"d", PhaseKind::Workers, 1.0, 2.0, 2, 1}};
    PhaseSummary s = summarizePhases(phases);
    CHECK(s.phaseSeconds == 7.0);
    CHECK(s.serialSeconds == 1.0);
    CHECK(s.workersSeconds == 4.0);
    CHECK(s.workersBusy == Approx(5.0 / 8.0));
}

TEST_CASE("timeWorkers takes the stage seconds gained during the run", "[engine]") {
    Stats stats;
    stats.local().stages[int(StageId::Surface)].seconds = 5.0; // before: not this phase's
    PhaseLog log;
    timeWorkers(&log, "work", stats, 4, [&] {
        stats.local().stages[int(StageId::Intersect)].seconds += 0.25;
    });
    REQUIRE(log.phases().size() == 1);
    CHECK(log.phases()[0].kind == PhaseKind::Workers);
    CHECK(log.phases()[0].busySeconds == Approx(0.25));
    CHECK(log.phases()[0].threads == 4);
}

TEST_CASE("The stage table lists the stages in pipeline order, each once", "[engine]") {
    const auto& order = enginePipeline();
    CHECK(order.front().id == StageId::CameraEmit);
    for (int i = 0; i < kFirstModeStage; ++i)
        CHECK(std::count_if(order.begin(), order.end(),
                            [&](const StageLabel& s) { return s.id == StageId(i); }) == 1);
    RenderStats r;
    std::string table = r.toTable();
    CHECK(table.find("camera") < table.find("intersect"));
    CHECK(table.find("intersect") < table.find("surface"));
    CHECK(table.find("gather") == std::string::npos); // the engine knows no mode's stages
    // A mode's stages follow the engine's, under the mode's names, with their own counters.
    r.pipeline = enginePipeline();
    r.pipeline.push_back({modeStage(1), "gather"});
    r.totals.stages[int(modeStage(1))].raysIn = 12345;
    table = r.toTable();
    CHECK(table.find("surface") < table.find("gather"));
    CHECK(table.find("12345", table.find("gather")) != std::string::npos);
    nlohmann::json j = nlohmann::json::parse(r.toJson());
    CHECK(j["pipeline"].back() == "gather");
    CHECK(j["stages"]["gather"]["rays"] == 12345);
}

} // namespace rayproc
