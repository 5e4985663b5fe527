// What a technique skipped, clamped or drew differently from what its options could give, counted
// per frame: each kind with its count, its ERRATA.md row and the option that changes it. The
// command line warns once per kind and the report explains differences from these records, so
// neither needs to know which technique made them (a technique declares its notes in its own files).
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace tessera {

struct FrameNote {
    std::string kind;         // a stable key: "eye-inside-volume", "light-list-overflow", ...
    std::string what;         // what was counted, plural, after the count: "lights skipped: the eye is inside their volume"
    std::uint64_t count = 0;  // how many (lights, entries, draws, pixels, ...)
    int erratum = 0;          // the ERRATA.md row; 0 for none
    std::string remedy;       // what changes it, as typed: "--option alphaTest=true", "--technique deferred"; empty for nothing
    bool visible = true;      // whether it changes the image (false: only costs, lists, counters)
};

// The notes of one frame (TechniqueContext::notes). Adding a kind already present adds to its
// count; passes may add from several threads.
class FrameNotes {
public:
    FrameNotes() = default;
    FrameNotes(const FrameNotes& other) : mNotes(other.list()) {}
    FrameNotes& operator=(const FrameNotes& other) {
        if (this != &other) {
            std::vector<FrameNote> copy = other.list();
            const std::lock_guard<std::mutex> lock(mMutex);
            mNotes = std::move(copy);
        }
        return *this;
    }
    // Adds `note` (a zero count adds nothing).
    void add(const FrameNote& note);
    // The notes in the order their kinds were first added.
    std::vector<FrameNote> list() const;
    // The note of `kind`, or a note with count 0.
    FrameNote find(const std::string& kind) const;
    void clear();

private:
    mutable std::mutex mMutex;
    std::vector<FrameNote> mNotes;
};

// "2 lights skipped: the eye is inside their volume (ERRATA.md #6; --technique deferred changes it)".
std::string noteText(const FrameNote& note);

} // namespace tessera
