// The argument loop every `tessera` command shares: walks the arguments after the command name,
// splits GNU long options `--width=64` into flag and value (as `--width 64`), and hands a flag
// its value or throws the usage error "--width needs a value". Bare words are operands (scenes,
// images); "-" alone is an operand too.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "render_args.h"  // UsageError

namespace tessera::cli {

class ArgCursor {
public:
    explicit ArgCursor(const std::vector<std::string_view>& args) : mArgs(args) {}

    // Moves to the next argument; false past the last one.
    bool next() {
        if (mPendingValue) throw UsageError(std::string(mFlag) + " takes no value (got '" + std::string(*mPendingValue) + "')");
        if (mIndex >= mArgs.size()) return false;
        const std::string_view a = mArgs[mIndex++];
        mPendingValue.reset();
        mFlag = a;
        if (a.size() > 2 && a.substr(0, 2) == "--") {
            if (const std::size_t eq = a.find('='); eq != std::string_view::npos) {
                mFlag = a.substr(0, eq);
                mPendingValue = a.substr(eq + 1);
            }
        }
        return true;
    }
    // The current argument's flag ("--width" for both "--width 64" and "--width=64"), or the
    // operand itself.
    std::string_view flag() const { return mFlag; }
    bool is(std::string_view name) const { return mFlag == name; }
    // True for "-x" and "--xyz" (not for "-" or an operand).
    bool isOption() const { return mFlag.size() > 1 && mFlag[0] == '-'; }
    // The flag's value: what followed '=', else the next argument.
    std::string_view value() {
        if (mPendingValue) {
            const std::string_view v = *mPendingValue;
            mPendingValue.reset();
            return v;
        }
        if (mIndex >= mArgs.size()) throw UsageError(std::string(mFlag) + " needs a value");
        return mArgs[mIndex++];
    }

private:
    const std::vector<std::string_view>& mArgs;
    std::size_t mIndex = 0;
    std::string_view mFlag;
    std::optional<std::string_view> mPendingValue;  // "--flag=VALUE": VALUE, until value() takes it
};

} // namespace tessera::cli
