#include "colon/connected_components.h"

#include <array>
#include <deque>
#include <stdexcept>

namespace colon {

std::vector<Component> labelComponents(const Grid& grid, std::vector<int32_t>& labels, int32_t firstLabel) {
    if (labels.size() != grid.voxelCount()) throw std::invalid_argument("labelComponents: labels do not fit the grid");
    std::vector<Component> components;
    std::deque<std::size_t> frontier;  // breadth-first: the queue holds a surface, not a volume
    const std::size_t count = labels.size();
    int32_t next = firstLabel;
    for (std::size_t seed = 0; seed < count; ++seed) {
        if (labels[seed] != kUnlabelled) continue;
        Component component;
        component.label = next++;
        labels[seed] = component.label;
        frontier.push_back(seed);
        while (!frontier.empty()) {
            const std::size_t n = frontier.front();
            frontier.pop_front();
            const auto [i, j, k] = grid.voxelOf(n);
            ++component.voxels;
            component.box.include(i, j, k);
            const std::array<std::array<int, 3>, 6> steps{
                {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}}};
            for (const auto& s : steps) {
                const int a = i + s[0], b = j + s[1], c = k + s[2];
                if (!grid.contains(a, b, c)) continue;
                const std::size_t m = grid.index(a, b, c);
                if (labels[m] != kUnlabelled) continue;
                labels[m] = component.label;
                frontier.push_back(m);
            }
        }
        components.push_back(component);
    }
    return components;
}

}  // namespace colon
