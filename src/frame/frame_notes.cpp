// FrameNotes (frame/frame_notes.h): the per-frame record of what a technique skipped or clamped,
// summed per kind, and its one-line text for warnings and the report.
#include <tessera/frame/frame_notes.h>

namespace tessera {

void FrameNotes::add(const FrameNote& note) {
    if (note.count == 0) return;
    const std::lock_guard<std::mutex> lock(mMutex);
    for (FrameNote& n : mNotes)
        if (n.kind == note.kind) {
            n.count += note.count;
            return;
        }
    mNotes.push_back(note);
}

std::vector<FrameNote> FrameNotes::list() const {
    const std::lock_guard<std::mutex> lock(mMutex);
    return mNotes;
}

FrameNote FrameNotes::find(const std::string& kind) const {
    const std::lock_guard<std::mutex> lock(mMutex);
    for (const FrameNote& n : mNotes)
        if (n.kind == kind) return n;
    return FrameNote{kind, "", 0, 0, "", true};
}

void FrameNotes::clear() {
    const std::lock_guard<std::mutex> lock(mMutex);
    mNotes.clear();
}

std::string noteText(const FrameNote& note) {
    std::string text = std::to_string(note.count) + " " + note.what;
    std::string why;
    if (note.erratum != 0) why = "ERRATA.md #" + std::to_string(note.erratum);
    if (!note.remedy.empty()) why += (why.empty() ? "" : "; ") + note.remedy + " changes it";
    if (!why.empty()) text += " (" + why + ")";
    return text;
}

} // namespace tessera
