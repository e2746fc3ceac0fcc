// The error of the teaching tools (heat maps, overlays, explain): a one-line message naming the
// option, the value and what to do, as every octrace error.
#pragma once

#include <stdexcept>

namespace oct {

class TeachError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

}  // namespace oct
