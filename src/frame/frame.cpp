// Frame::run: executes passes in order and checks their read/write declarations; auditBuffers:
// why each buffer of a run exists.
#include <tessera/frame/frame.h>

#include <algorithm>
#include <stdexcept>

namespace tessera {

namespace {

bool lists(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

} // namespace

std::vector<PassTiming> Frame::run(BufferRegistry& registry, const AfterPass& afterPass, bool inspection) const {
    std::vector<PassTiming> timings;
    for (const Pass& pass : mPasses) {
        if (!inspection && pass.inspectionOnly()) continue;
        for (const std::string& r : pass.reads)
            if (!registry.contains(r))
                throw std::logic_error("pass '" + pass.name + "' reads buffer '" + r + "' that no earlier pass wrote");
        const std::size_t registeredBefore = registry.names().size();
        const auto start = std::chrono::steady_clock::now();
        if (pass.execute) pass.execute(registry);
        const auto stop = std::chrono::steady_clock::now();
        for (const std::string& w : pass.writes)
            if (!registry.contains(w))
                throw std::logic_error("pass '" + pass.name + "' declares buffer '" + w + "' but did not register it");
        for (std::size_t i = registeredBefore; i < registry.names().size(); ++i)
            if (!lists(pass.writes, registry.names()[i]))
                throw std::logic_error("pass '" + pass.name + "' registered buffer '" + registry.names()[i] + "' that it does not declare");
        for (const std::string& v : pass.inspection)
            if (!lists(pass.writes, v))
                throw std::logic_error("pass '" + pass.name + "' declares inspection buffer '" + v + "' that it does not write");
        timings.push_back({pass.name, std::chrono::duration<double, std::milli>(stop - start).count()});
        if (afterPass) afterPass(pass, registry);
    }
    return timings;
}

std::vector<BufferUse> auditBuffers(const Frame& frame, const BufferRegistry& registry, std::span<const std::string_view> images,
                                    bool inspection) {
    const std::vector<Pass>& passes = frame.passes();
    std::vector<BufferUse> uses;
    for (const std::string& name : registry.names()) {
        BufferUse use;
        use.name = name;
        const Surface* surface = registry.find(name);
        use.bytes = surface ? surface->bytes().size() : 0;
        bool written = false, forInspection = false;
        for (const Pass& pass : passes) {
            if (!inspection && pass.inspectionOnly()) continue;
            if (written && lists(pass.reads, name) && !lists(use.readBy, pass.name)) use.readBy.push_back(pass.name);
            if (lists(pass.writes, name)) {
                if (!written) use.firstWriter = pass.name;
                written = true;
                forInspection = lists(pass.inspection, name);  // the last writer's word
            }
        }
        use.role = !use.readBy.empty()   ? BufferUse::Role::Read
                   : std::find(images.begin(), images.end(), name) != images.end() ? BufferUse::Role::Image
                   : forInspection       ? BufferUse::Role::Inspection
                                         : BufferUse::Role::Unread;
        uses.push_back(std::move(use));
    }
    return uses;
}

} // namespace tessera
