// Frame::run's checks of the passes' declarations (a read before any write, a declared write left
// unregistered, a buffer registered without being declared, an inspection buffer not written),
// auditBuffers' roles on a hand-made frame whose every buffer's role is known, and run() without
// inspection skipping the passes that only write inspection buffers.
#include <doctest/doctest.h>

#include <array>
#include <stdexcept>
#include <string_view>

#include <tessera/frame/frame.h>

// One namespace per test file: the files of a folder compile as one unity batch (tests/CMakeLists.txt).
namespace tessera_test::frame_frame_test {

using namespace tessera;

namespace {

const SurfaceDesc kDesc{4, 2, Format::R8G8B8A8_UNORM, 1};  // 4 x 2 px x 4 B = 32 B

Pass creating(std::string name, std::vector<std::string> reads, std::vector<std::string> writes, std::vector<std::string> creates,
              std::vector<std::string> inspection = {}) {
    return {std::move(name), std::move(reads), std::move(writes),
            [creates](BufferRegistry& reg) {
                for (const std::string& c : creates) reg.create(c, kDesc);
            },
            std::move(inspection)};
}

} // namespace

TEST_CASE("frame: run refuses a pass whose declarations do not match what it registers") {
    BufferRegistry reg;
    Frame undeclared;
    undeclared.add(creating("clear", {}, {"a"}, {"a", "b"}));
    CHECK_THROWS_WITH_AS(undeclared.run(reg), "pass 'clear' registered buffer 'b' that it does not declare", std::logic_error);

    reg.clear();
    Frame unregistered;
    unregistered.add(creating("clear", {}, {"a", "b"}, {"a"}));
    CHECK_THROWS_WITH_AS(unregistered.run(reg), "pass 'clear' declares buffer 'b' but did not register it", std::logic_error);

    reg.clear();
    Frame earlyRead;
    earlyRead.add(creating("shade", {"a"}, {"b"}, {"b"}));
    CHECK_THROWS_WITH_AS(earlyRead.run(reg), "pass 'shade' reads buffer 'a' that no earlier pass wrote", std::logic_error);

    reg.clear();
    Frame inspectionNotWritten;
    inspectionNotWritten.add(creating("cull", {}, {"a"}, {"a"}, {"heat"}));
    CHECK_THROWS_WITH_AS(inspectionNotWritten.run(reg), "pass 'cull' declares inspection buffer 'heat' that it does not write",
                         std::logic_error);

    // A buffer an earlier pass registered may be written again without registering anything.
    reg.clear();
    Frame rewrite;
    rewrite.add(creating("clear", {}, {"a"}, {"a"}));
    rewrite.add(creating("draw", {"a"}, {"a"}, {"a"}));  // create() of an existing buffer returns it
    CHECK_NOTHROW(rewrite.run(reg));
}

TEST_CASE("frame: auditBuffers gives each buffer the role the declarations imply") {
    // clear: registers backbuffer, depth, grid, heat (inspection), spare; cull: reads depth,
    // writes grid; shade: reads grid, depth, writes backbuffer. Expected: backbuffer Image (no pass
    // after clear reads it), depth Read by cull and shade, grid Read by shade (after clear wrote
    // it), heat Inspection, spare Unread.
    Frame frame;
    frame.add(creating("clear", {}, {"backbuffer", "depth", "grid", "heat", "spare"}, {"backbuffer", "depth", "grid", "heat", "spare"},
                       {"heat"}));
    frame.add(creating("cull", {"depth"}, {"grid"}, {}));
    frame.add(creating("shade", {"grid", "depth"}, {"backbuffer"}, {}));
    BufferRegistry reg;
    frame.run(reg);
    const std::array<std::string_view, 1> images{"backbuffer"};
    const std::vector<BufferUse> uses = auditBuffers(frame, reg, images);
    REQUIRE(uses.size() == 5);
    using Role = BufferUse::Role;
    CHECK(uses[0].name == "backbuffer");
    CHECK(uses[0].role == Role::Image);
    CHECK(uses[1].name == "depth");
    CHECK(uses[1].role == Role::Read);
    CHECK(uses[1].readBy == std::vector<std::string>{"cull", "shade"});
    CHECK(uses[2].name == "grid");
    CHECK(uses[2].role == Role::Read);
    CHECK(uses[2].readBy == std::vector<std::string>{"shade"});
    CHECK(uses[3].name == "heat");
    CHECK(uses[3].role == Role::Inspection);
    CHECK(uses[4].name == "spare");
    CHECK(uses[4].role == Role::Unread);
    for (const BufferUse& u : uses) {
        CHECK(u.firstWriter == "clear");
        CHECK(u.bytes == 32);
    }
    // Without the image's name the back buffer is read by nothing.
    CHECK(auditBuffers(frame, reg, {})[0].role == Role::Unread);
}

TEST_CASE("frame: without inspection, run skips the passes that only write inspection buffers, and the audit ignores them") {
    // clear: a; heat: reads a and only, writes h (inspection); shade: reads a, writes b.
    Frame frame;
    frame.add(creating("clear", {}, {"a", "only"}, {"a", "only"}));
    frame.add(creating("heat", {"a", "only"}, {"h"}, {"h"}, {"h"}));
    frame.add(creating("shade", {"a"}, {"b"}, {"b"}));
    CHECK_FALSE(frame.passes()[0].inspectionOnly());
    CHECK(frame.passes()[1].inspectionOnly());
    BufferRegistry reg;
    std::vector<PassTiming> t = frame.run(reg, {}, false);
    REQUIRE(t.size() == 2);
    CHECK(t[0].name == "clear");
    CHECK(t[1].name == "shade");
    CHECK_FALSE(reg.contains("h"));
    // "only" is read by the skipped pass alone: nothing that ran reads it.
    CHECK(auditBuffers(frame, reg, {}, false)[1].role == BufferUse::Role::Unread);
    reg.clear();
    t = frame.run(reg);
    CHECK(t.size() == 3);
    CHECK(reg.contains("h"));
    const std::vector<BufferUse> uses = auditBuffers(frame, reg, {});
    CHECK(uses[1].role == BufferUse::Role::Read);
    CHECK(uses[2].name == "h");
    CHECK(uses[2].role == BufferUse::Role::Inspection);
}

} // namespace tessera_test::frame_frame_test
