// A frame is an ordered list of named passes; each pass declares the named buffers it reads
// and writes. run() executes them in order, checks the declarations against the registry
// (a read of a buffer no earlier pass wrote, a declared write left unregistered, or a buffer
// registered by a pass that does not declare it, is an error naming the pass and buffer) and
// times every pass for --stats. auditBuffers() says why each buffer of a run exists.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string_view>
#include <string>
#include <vector>

#include <tessera/frame/buffer_registry.h>

namespace tessera {

struct Pass {
    std::string name;
    std::vector<std::string> reads;
    std::vector<std::string> writes;
    std::function<void(BufferRegistry&)> execute;
    // Of `writes`: the buffers written only to be looked at (--dump, probe, the report), which no
    // later pass reads: a light grid's heat map, a culling pass's per-tile counters, a draw's own
    // depth target. A pass whose every write is listed here has no other effect on the frame (the
    // technique's promise: run() may skip it).
    std::vector<std::string> inspection = {};
    bool inspectionOnly() const { return !writes.empty() && inspection.size() == writes.size(); }
};

// Why a buffer of a frame's run exists (auditBuffers).
struct BufferUse {
    enum class Role : std::uint8_t {
        Read,        // a later pass reads it
        Image,       // "backbuffer": the frame's result
        Inspection,  // declared by its last writer as written to be looked at
        Unread       // none of these: allocated for nothing (the audit's failure)
    };
    std::string name;
    std::uint64_t bytes = 0;
    std::string firstWriter;             // the pass that registered it
    std::vector<std::string> readBy;     // passes after a write that read it, in frame order
    Role role = Role::Unread;
};

// Every buffer of `registry` (as a run of `frame` left it), in registration order, with its role.
// A buffer's role is Read when a pass after its first writer declares reading it, else Image when
// `images` names it (the frame's results: the back buffer, precision reference's float copy), else
// Inspection when its last writer declares it so, else Unread. `inspection`: as given to run()
// (without it, inspection-only passes did not run and read nothing).
std::vector<BufferUse> auditBuffers(const class Frame& frame, const BufferRegistry& registry,
                                    std::span<const std::string_view> images, bool inspection = true);

struct PassTiming {
    std::string name;
    double milliseconds = 0.0;
};

class Frame {
public:
    Frame& add(Pass pass) {
        mPasses.push_back(std::move(pass));
        return *this;
    }
    const std::vector<Pass>& passes() const { return mPasses; }
    // Called after each pass with the registry as that pass left it (outside the pass's time).
    using AfterPass = std::function<void(const Pass&, const BufferRegistry&)>;
    // Runs every pass in order; throws std::logic_error on a broken declaration. Without
    // `inspection`, passes that only write inspection buffers (Pass::inspectionOnly: a heat map,
    // a contribution drawn apart to be looked at) are skipped and get no timing: a frame whose
    // intermediate buffers nobody will look at does only the work its image needs.
    std::vector<PassTiming> run(BufferRegistry& registry, const AfterPass& afterPass = {}, bool inspection = true) const;

private:
    std::vector<Pass> mPasses;
};

} // namespace tessera
