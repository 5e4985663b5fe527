// A frame is an ordered list of named passes; each pass declares the named buffers it reads
// and writes. run() executes them in order, checks the declarations against the registry
// (a read of a buffer no earlier pass wrote, or a declared write left unregistered, is an
// error naming the pass and buffer) and times every pass for --stats.
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include <tessera/frame/buffer_registry.h>

namespace tessera {

struct Pass {
    std::string name;
    std::vector<std::string> reads;
    std::vector<std::string> writes;
    std::function<void(BufferRegistry&)> execute;
};

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
    // Runs every pass in order; throws std::logic_error on a broken declaration.
    std::vector<PassTiming> run(BufferRegistry& registry, const AfterPass& afterPass = {}) const;

private:
    std::vector<Pass> mPasses;
};

} // namespace tessera
