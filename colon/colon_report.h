/// @brief What `cvc colon` writes about an analysis: the centreline as the text `--path`
/// reads, and colon.json (the phantom truth's "centreline_mm" plus segments, gaps, the air
/// regions with the measures their class came from, and the cleansing summary).
#pragma once

#include <string>

#include "colon/colon_analysis.h"

namespace colon {

/// One "x y z" line per point in volume millimetres, rectum -> caecum; a line "# segment N"
/// starts each segment.
std::string centrelineText(const ColonAnalysis& analysis);

/// colon.json. "centreline_mm" holds every segment's points in antegrade order, and
/// "segment_starts" the index at which each segment begins, so a reader can fly segment by
/// segment without crossing the gaps through tissue.
std::string colonJson(const ColonAnalysis& analysis, const volumes::Volume& volume, const std::string& volumePath);

}  // namespace colon
