#include "engine/review/review_volume.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace engine {
namespace {

/// A grid axis lying further than this from its patient axis (cos 8 degrees) makes the labels
/// approximate.
constexpr double kAlignedCosine = 0.990;

/// Which grid axis shows each patient axis (L, P, S), and whether the grid index grows toward
/// +L, +P, +S: the permutation of grid axes that lies nearest to the patient axes.
struct PatientAxes {
    std::array<int, 3> gridAxis{0, 1, 2};
    std::array<int, 3> sign{1, 1, 1};
    double worstCosine = 1.0;
};

PatientAxes patientAxesOf(const glm::dmat3& directionLps) {
    // directionLps[a] is grid axis a's unit vector in LPS; directionLps[a][p] its component along p.
    std::array<int, 3> permutation{0, 1, 2};
    std::array<int, 3> best = permutation;
    double bestScore = -1.0;
    do {
        double score = 1.0;
        for (int p = 0; p < 3; ++p) score *= std::abs(directionLps[permutation[p]][p]);
        if (score > bestScore) {
            bestScore = score;
            best = permutation;
        }
    } while (std::next_permutation(permutation.begin(), permutation.end()));
    PatientAxes axes;
    axes.gridAxis = best;
    for (int p = 0; p < 3; ++p) {
        const double component = directionLps[best[p]][p];
        axes.sign[p] = component < 0.0 ? -1 : 1;
        axes.worstCosine = std::min(axes.worstCosine, std::abs(component));
    }
    return axes;
}

/// A view in patient terms: the patient axis across the slices, and the patient axis (with the
/// way it runs) along the image's columns (left to right) and rows (top to bottom).
struct PatientView {
    const char* name;
    int normal;
    int column, columnDirection;
    int row, rowDirection;
    const char *left, *right, *top, *bottom;
};

constexpr int kL = 0, kP = 1, kS = 2;

constexpr PatientView kPatientViews[3] = {
    {"axial", kS, kL, +1, kP, +1, "R", "L", "A", "P"},
    {"coronal", kP, kL, +1, kS, -1, "R", "L", "S", "I"},
    {"sagittal", kL, kP, +1, kS, -1, "A", "P", "S", "I"},
};

}  // namespace

uint8_t reviewGrey(double hu) {
    const double t = (hu - (kReviewWindowLevelHu - 0.5 * kReviewWindowWidthHu)) / kReviewWindowWidthHu;
    return static_cast<uint8_t>(std::lround(255.0 * std::clamp(t, 0.0, 1.0)));
}

std::array<ReviewSliceView, 3> reviewSliceViews(const glm::dmat3& directionLps, bool* isOblique) {
    const PatientAxes axes = patientAxesOf(directionLps);
    if (isOblique) *isOblique = axes.worstCosine < kAlignedCosine;
    std::array<ReviewSliceView, 3> views;
    for (int v = 0; v < 3; ++v) {
        const PatientView& p = kPatientViews[v];
        ReviewSliceView& view = views[static_cast<std::size_t>(v)];
        view.name = p.name;
        view.normalAxis = axes.gridAxis[p.normal];
        view.columnAxis = axes.gridAxis[p.column];
        view.rowAxis = axes.gridAxis[p.row];
        view.isColumnFlipped = axes.sign[p.column] * p.columnDirection < 0;
        view.isRowFlipped = axes.sign[p.row] * p.rowDirection < 0;
        view.leftLabel = p.left;
        view.rightLabel = p.right;
        view.topLabel = p.top;
        view.bottomLabel = p.bottom;
    }
    return views;
}

ReviewVolume reviewVolumeOf(const volumes::Volume& volume, int maxSide) {
    if (maxSide < 1) throw std::invalid_argument("review volume: the largest side must be at least 1 voxel");
    if (volume.voxelCount() == 0 || volume.hu.size() != volume.voxelCount()) {
        throw std::invalid_argument("review volume: the volume holds no voxels");
    }
    ReviewVolume out;
    for (int a = 0; a < 3; ++a) {
        const int n = volume.dims[static_cast<std::size_t>(a)];
        const int f = (n + maxSide - 1) / maxSide;
        out.factor[static_cast<std::size_t>(a)] = f;
        out.dims[static_cast<std::size_t>(a)] = (n + f - 1) / f;
        out.spacingMm[a] = volume.spacingMm[a] * f;
        out.offsetMm[a] = volume.spacingMm[a] * 0.5 * (f - 1);  // the centre of a full block
    }
    const auto [nx, ny, nz] = out.dims;
    const auto [fx, fy, fz] = out.factor;
    const std::size_t reducedCount = static_cast<std::size_t>(nx) * ny * nz;
    std::vector<int64_t> sum(reducedCount, 0);
    std::vector<int32_t> count(reducedCount, 0);
    std::vector<std::size_t> reducedColumn(static_cast<std::size_t>(volume.dims[0]));  // no division per voxel
    for (int i = 0; i < volume.dims[0]; ++i) reducedColumn[static_cast<std::size_t>(i)] = static_cast<std::size_t>(i / fx);
    for (int k = 0; k < volume.dims[2]; ++k) {
        for (int j = 0; j < volume.dims[1]; ++j) {
            const std::size_t row = static_cast<std::size_t>(j / fy) * nx + static_cast<std::size_t>(k / fz) * nx * ny;
            const int16_t* source = volume.hu.data() + volume.linearIndex(0, j, k);
            for (std::size_t i = 0; i < reducedColumn.size(); ++i) {
                const std::size_t r = row + reducedColumn[i];
                sum[r] += source[i];
                ++count[r];
            }
        }
    }
    out.grey.resize(reducedCount);
    for (std::size_t r = 0; r < reducedCount; ++r) {
        out.grey[r] = reviewGrey(static_cast<double>(sum[r]) / count[r]);
    }
    out.views = reviewSliceViews(volume.directionLps, &out.isOblique);
    out.directionLps = volume.directionLps;
    return out;
}

std::string base64Of(const std::vector<uint8_t>& bytes) {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string text;
    text.reserve((bytes.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const uint32_t triple = (uint32_t{bytes[i]} << 16) | (uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
        text += kAlphabet[(triple >> 18) & 63];
        text += kAlphabet[(triple >> 12) & 63];
        text += kAlphabet[(triple >> 6) & 63];
        text += kAlphabet[triple & 63];
    }
    if (i + 1 == bytes.size()) {
        const uint32_t single = uint32_t{bytes[i]} << 16;
        text += kAlphabet[(single >> 18) & 63];
        text += kAlphabet[(single >> 12) & 63];
        text += "==";
    } else if (i + 2 == bytes.size()) {
        const uint32_t pair = (uint32_t{bytes[i]} << 16) | (uint32_t{bytes[i + 1]} << 8);
        text += kAlphabet[(pair >> 18) & 63];
        text += kAlphabet[(pair >> 12) & 63];
        text += kAlphabet[(pair >> 6) & 63];
        text += '=';
    }
    return text;
}

}  // namespace engine
