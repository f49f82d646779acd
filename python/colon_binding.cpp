// cvc.colon: the colon analysis of `cvc colon` (segmentation, cleansing, centreline) as Python
// objects: what colon.json holds, the lumen and labels as numpy masks, the cleansed volume.
#include <memory>
#include <string>

#include <pybind11/numpy.h>

#include "colon/colon_analysis.h"
#include "colon/colon_report.h"
#include "python/bindings.h"
#include "python/gpu_session.h"
#include "volumes/brick_minmax.h"

namespace py = pybind11;

namespace cvc_python {
namespace {

py::dict colonOf(const SessionVolume& given, double airThresholdHu, bool cleanse) {
    // The analysis cleanses tagged fluid in place: it works on a copy, so the caller's volume
    // stays as it was, and the cleansed one comes back on its own.
    auto working = std::make_unique<volumes::Volume>(given.volume());
    colon::ColonSettings settings;
    settings.segmentation.airThresholdHu = airThresholdHu;
    settings.cleansing = cleanse ? colon::Cleansing::Auto : colon::Cleansing::Off;
    colon::ColonAnalysis analysis;
    std::string json;
    {
        py::gil_scoped_release release;
        analysis = colon::analyseColon(*working, settings);
        json = colon::colonJson(analysis, *working, given.source());
    }
    py::dict result = py::module_::import("json").attr("loads")(json);
    const auto& dims = analysis.labels.dims;
    const std::vector<py::ssize_t> shape = {dims[2], dims[1], dims[0]};
    py::array_t<int16_t> labels(shape);
    std::copy(analysis.labels.hu.begin(), analysis.labels.hu.end(), labels.mutable_data());
    py::array_t<uint8_t> lumen(shape);
    uint8_t* mask = lumen.mutable_data();
    for (std::size_t n = 0; n < analysis.labels.hu.size(); ++n) mask[n] = analysis.labels.hu[n] >= colon::kLabelFirstSegment ? 1 : 0;
    result["labels"] = labels;
    result["lumen"] = lumen;
    if (analysis.isCleansed) {
        volumes::LoadedVolume cleansed;
        cleansed.volume = std::move(*working);
        cleansed.bricks = volumes::buildBrickMinMax(cleansed.volume);
        result["cleansed_volume"] = std::make_shared<SessionVolume>(std::move(cleansed), given.source() + " (cleansed)");
    } else {
        result["cleansed_volume"] = py::none();
    }
    return result;
}

}  // namespace

void addColonBindings(py::module_& module) {
    module.def("colon", &colonOf, py::arg("volume"), py::kw_only(), py::arg("air_threshold") = -800.0,
               py::arg("cleanse") = true,
               "The colon analysis of `cvc colon`: a dict of what colon.json holds (centreline_mm, segment_starts, "
               "segments, gaps, air regions, cleansing), plus 'lumen' (uint8 (z, y, x) mask of the colon's segments), "
               "'labels' (int16 label codes) and 'cleansed_volume' (a cvc.Volume, or None when nothing was cleansed). "
               "The given volume is not changed.");
}

}  // namespace cvc_python
