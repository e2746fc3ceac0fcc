#include "core/octree/layout_registry.h"

#include <type_traits>

namespace oct {
namespace {

template <class L>
NodeLookup lookupIn(const LayoutStorage& s, uint64_t key) {
    return lookupNode(s.as<typename L::View>(), key);
}

template <class L, class = void>
struct HasBuildLimit : std::false_type {};
template <class L>
struct HasBuildLimit<L, std::void_t<decltype(&L::limitBuild)>> : std::true_type {};

template <class L>
void limitBuildOf(BuildParams& build, const LayoutOptions& o) {
    if constexpr (HasBuildLimit<L>::value) L::limitBuild(build, o);
}

template <class L>
LayoutDesc describe(int index) {
    return {index,       L::kName,   L::kSummary,  L::kUsesOctree,  L::kSkipReasons,
            &L::convert, &L::report, &lookupIn<L>, &limitBuildOf<L>};
}

template <class... L>
std::vector<LayoutDesc> describeAll(LayoutList<L...>) {
    int i = 0;
    return {describe<L>(i++)...};
}

}  // namespace

const std::vector<LayoutDesc>& layouts() {
    static const std::vector<LayoutDesc> all = describeAll(Layouts{});
    return all;
}

std::string layoutNames() {
    std::string s;
    for (const LayoutDesc& d : layouts()) s += (s.empty() ? "" : ", ") + std::string(d.name);
    return s;
}

const LayoutDesc& findLayout(const std::string& name) {
    for (const LayoutDesc& d : layouts())
        if (name == d.name) return d;
    throw OctreeError("unknown --accel '" + name + "': use " + layoutNames());
}

}  // namespace oct
