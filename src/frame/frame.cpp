// Frame::run: executes passes in order and checks their read/write declarations.
#include <tessera/frame/frame.h>

#include <stdexcept>

namespace tessera {

std::vector<PassTiming> Frame::run(BufferRegistry& registry, const AfterPass& afterPass) const {
    std::vector<PassTiming> timings;
    for (const Pass& pass : mPasses) {
        for (const std::string& r : pass.reads)
            if (!registry.contains(r))
                throw std::logic_error("pass '" + pass.name + "' reads buffer '" + r + "' that no earlier pass wrote");
        const auto start = std::chrono::steady_clock::now();
        if (pass.execute) pass.execute(registry);
        const auto stop = std::chrono::steady_clock::now();
        for (const std::string& w : pass.writes)
            if (!registry.contains(w))
                throw std::logic_error("pass '" + pass.name + "' declares buffer '" + w + "' but did not register it");
        timings.push_back({pass.name, std::chrono::duration<double, std::milli>(stop - start).count()});
        if (afterPass) afterPass(pass, registry);
    }
    return timings;
}

} // namespace tessera
