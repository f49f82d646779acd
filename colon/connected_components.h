/// @brief Connected-component labelling of a voxel mask (6-connected: two air voxels that
/// touch only at an edge or a corner stay apart, so air does not leak through a wall one voxel
/// thin).
#pragma once

#include <cstdint>
#include <vector>

#include "colon/grid.h"

namespace colon {

/// One component: its label, size and bounding box.
struct Component {
    int32_t label = 0;
    std::size_t voxels = 0;
    VoxelBox box;
};

/// Value of `labels` for a voxel that belongs to the mask but has no component yet.
inline constexpr int32_t kUnlabelled = -1;

/// Labels the voxels of `labels` that hold kUnlabelled with 1, 2, ... by 6-connected
/// component, in the order of their first voxel (x fastest); other values are left as they
/// are and never joined. Labels start at `firstLabel`. Returns the components found.
std::vector<Component> labelComponents(const Grid& grid, std::vector<int32_t>& labels, int32_t firstLabel = 1);

}  // namespace colon
