#include "core/render/film.h"

namespace oct {

Film::Film(int w, int h)
    : width(w),
      height(h),
      rgb(size_t(w) * size_t(h) * 3),
      t(size_t(w) * size_t(h)),
      prim(size_t(w) * size_t(h)),
      nodes(size_t(w) * size_t(h)),
      primsTested(size_t(w) * size_t(h)),
      shadow(size_t(w) * size_t(h)) {}

FilmView Film::view() {
    return {rgb.data(),         t.data(),      prim.data(), nodes.data(),
            primsTested.data(), shadow.data(), width,       height};
}

std::vector<int32_t> costArray(const Film& film) {
    std::vector<int32_t> cost(film.pixelCount() * 2);
    for (size_t i = 0; i < film.pixelCount(); ++i) {
        cost[2 * i] = int32_t(film.nodes[i]);
        cost[2 * i + 1] = int32_t(film.primsTested[i]);
    }
    return cost;
}

}  // namespace oct
