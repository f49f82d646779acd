/// @brief Benchmarks of the volumes module on a 512 x 512 x 451 CT (the abdomen of
/// ../shared/data resampled trilinearly): brick min/max build time, load time and peak memory
/// per format. Timings, not assertions; scripts/bench/bench_volumes.sh runs every step.
///
///   volumes_bench make FOLDER   writes ct.nrrd, ct_gzip.nrrd, ct.mha (zlib), ct.nii.gz, ct.vdb
///                               and a DICOM series dicom/ (one file per slice)
///   volumes_bench load PATH     loads PATH once and prints time and peak resident memory
///   volumes_bench bricks PATH   times buildBrickMinMax (median of 7) on the loaded volume
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sys/resource.h>
#include <thread>

#include <gdcmAttribute.h>
#include <gdcmImageWriter.h>
#include <gdcmTrace.h>
#include <gdcmUIDGenerator.h>
#include <gdcmUIDs.h>
#include <zlib.h>

#include "volumes/brick_minmax.h"
#include "volumes/load_volume.h"
#include "volumes/nrrd_io.h"
#include "volumes/vdb_io.h"

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

double peakResidentMiB() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

/// The abdomen resampled to 512 x 512 x 451 over the same box (trilinear).
volumes::Volume makeLargeCt() {
    const volumes::Volume small =
        volumes::loadVolume(std::string(CVC_SHARED_DATA_DIR) + "/ct/ts_example_abdomen_3mm.nrrd");
    volumes::Volume large;
    large.dims = {512, 512, 451};
    for (int a = 0; a < 3; ++a) {
        large.spacingMm[a] = small.spacingMm[a] * (small.dims[static_cast<std::size_t>(a)] - 1) /
                             (large.dims[static_cast<std::size_t>(a)] - 1);
    }
    large.originLps = small.originLps;
    large.directionLps = small.directionLps;
    large.hu.resize(large.voxelCount());
    for (int k = 0; k < large.dims[2]; ++k) {
        const double z = k * large.spacingMm.z / small.spacingMm.z;
        const int z0 = std::min(static_cast<int>(z), small.dims[2] - 2);
        const double tz = z - z0;
        for (int j = 0; j < large.dims[1]; ++j) {
            const double y = j * large.spacingMm.y / small.spacingMm.y;
            const int y0 = std::min(static_cast<int>(y), small.dims[1] - 2);
            const double ty = y - y0;
            for (int i = 0; i < large.dims[0]; ++i) {
                const double x = i * large.spacingMm.x / small.spacingMm.x;
                const int x0 = std::min(static_cast<int>(x), small.dims[0] - 2);
                const double tx = x - x0;
                double v = 0.0;
                for (int c = 0; c < 8; ++c) {
                    const double w = ((c & 1) ? tx : 1 - tx) * ((c & 2) ? ty : 1 - ty) * ((c & 4) ? tz : 1 - tz);
                    v += w * small.at(x0 + (c & 1), y0 + ((c >> 1) & 1), z0 + ((c >> 2) & 1));
                }
                large.hu[large.linearIndex(i, j, k)] = static_cast<int16_t>(std::lround(v));
            }
        }
    }
    return large;
}

std::string deflated(const char* data, std::size_t bytes, bool isGzip) {
    z_stream stream{};
    deflateInit2(&stream, 1, Z_DEFLATED, isGzip ? 31 : 15, 8, Z_DEFAULT_STRATEGY);
    std::string out(deflateBound(&stream, static_cast<uLong>(bytes)), '\0');
    stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data));
    stream.avail_in = static_cast<uInt>(bytes);
    stream.next_out = reinterpret_cast<Bytef*>(out.data());
    stream.avail_out = static_cast<uInt>(out.size());
    deflate(&stream, Z_FINISH);
    out.resize(stream.total_out);
    deflateEnd(&stream);
    return out;
}

void writeDicomSeries(const volumes::Volume& v, const std::string& folder) {
    std::filesystem::create_directories(folder);
    gdcm::Trace::SetWarning(false);  // the writer warns about every attribute it defaults
    gdcm::UIDGenerator uids;
    const std::string studyUid = uids.Generate(), seriesUid = uids.Generate();
    const std::size_t sliceVoxels = static_cast<std::size_t>(v.dims[0]) * v.dims[1];
    for (int k = 0; k < v.dims[2]; ++k) {
        gdcm::ImageWriter writer;
        gdcm::Image& image = writer.GetImage();
        image.SetNumberOfDimensions(2);
        image.SetDimension(0, static_cast<unsigned>(v.dims[0]));
        image.SetDimension(1, static_cast<unsigned>(v.dims[1]));
        image.SetPixelFormat(gdcm::PixelFormat::INT16);
        image.SetPhotometricInterpretation(gdcm::PhotometricInterpretation::MONOCHROME2);
        const glm::dvec3 origin = v.originLps + v.directionLps[2] * (k * v.spacingMm.z);
        const double position[3] = {origin.x, origin.y, origin.z};
        const double cosines[6] = {v.directionLps[0].x, v.directionLps[0].y, v.directionLps[0].z,
                                   v.directionLps[1].x, v.directionLps[1].y, v.directionLps[1].z};
        const double spacing[3] = {v.spacingMm.x, v.spacingMm.y, v.spacingMm.z};
        image.SetOrigin(position);
        image.SetOrigin(2, position[2]);  // a 2D image keeps only two coordinates otherwise
        image.SetDirectionCosines(cosines);
        image.SetSpacing(spacing);
        gdcm::DataElement pixels(gdcm::Tag(0x7fe0, 0x0010));
        pixels.SetByteValue(reinterpret_cast<const char*>(v.hu.data() + k * sliceVoxels),
                            static_cast<uint32_t>(sliceVoxels * sizeof(int16_t)));
        image.SetDataElement(pixels);
        gdcm::DataSet& ds = writer.GetFile().GetDataSet();
        const char* ctStorage = gdcm::UIDs::GetUIDString(gdcm::UIDs::CTImageStorage);
        gdcm::DataElement sopClass(gdcm::Tag(0x0008, 0x0016));
        sopClass.SetByteValue(ctStorage, static_cast<uint32_t>(std::strlen(ctStorage)));
        sopClass.SetVR(gdcm::VR::UI);
        ds.Replace(sopClass);
        gdcm::Attribute<0x0020, 0x000d> study{studyUid};
        gdcm::Attribute<0x0020, 0x000e> series{seriesUid};
        gdcm::Attribute<0x0008, 0x0060> modality{"CT"};
        ds.Replace(study.GetAsDataElement());
        ds.Replace(series.GetAsDataElement());
        ds.Replace(modality.GetAsDataElement());
        const std::string path = folder + "/slice" + std::to_string(1000 + k) + ".dcm";
        writer.SetFileName(path.c_str());
        if (!writer.Write()) throw volumes::VolumeError(path + ": GDCM could not write it");
    }
}

void make(const std::string& folder) {
    std::filesystem::create_directories(folder);
    const volumes::Volume v = makeLargeCt();
    const std::size_t bytes = v.hu.size() * sizeof(int16_t);
    const char* data = reinterpret_cast<const char*>(v.hu.data());
    volumes::writeNrrd(v, folder + "/ct.nrrd", true);

    // gzip NRRD: the raw writer's header with the encoding changed.
    std::ifstream in(folder + "/ct.nrrd", std::ios::binary);
    std::string header, line;
    while (std::getline(in, line) && !line.empty())
        header += (line == "encoding: raw" ? "encoding: gzip" : line) + "\n";
    std::ofstream(folder + "/ct_gzip.nrrd", std::ios::binary) << header << "\n" << deflated(data, bytes, true);

    std::ostringstream mha;
    mha << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\nCompressedData = True\n"
        << "TransformMatrix = -1 0 0 0 -1 0 0 0 1\nOffset = " << v.originLps.x << ' ' << v.originLps.y << ' '
        << v.originLps.z << "\nElementSpacing = " << v.spacingMm.x << ' ' << v.spacingMm.y << ' ' << v.spacingMm.z
        << "\nDimSize = 512 512 451\nElementType = MET_SHORT\nElementDataFile = LOCAL\n";
    std::ofstream(folder + "/ct.mha", std::ios::binary) << mha.str() << deflated(data, bytes, false);

    // NIfTI-1, int16, sform from the LPS grid (RAS: x and y negated), gzip as a whole.
    std::string nifti(352, '\0');
    auto put = [&](std::size_t offset, const auto& value) {
        std::memcpy(nifti.data() + offset, &value, sizeof(value));
    };
    put(0, int32_t{348});
    const short dim[8] = {3, 512, 512, 451, 1, 1, 1, 1};
    std::memcpy(nifti.data() + 40, dim, sizeof(dim));
    put(70, short{4});
    put(72, short{16});
    const float pixdim[8] = {1,
                             static_cast<float>(v.spacingMm.x),
                             static_cast<float>(v.spacingMm.y),
                             static_cast<float>(v.spacingMm.z),
                             1,
                             1,
                             1,
                             1};
    std::memcpy(nifti.data() + 76, pixdim, sizeof(pixdim));
    put(108, 352.0f);
    put(254, short{1});
    for (int r = 0; r < 3; ++r) {
        const double sign = r < 2 ? -1.0 : 1.0;
        float row[4];
        for (int c = 0; c < 3; ++c) row[c] = static_cast<float>(sign * v.directionLps[c][r] * v.spacingMm[c]);
        row[3] = static_cast<float>(sign * v.originLps[r]);
        std::memcpy(nifti.data() + 280 + 16 * r, row, sizeof(row));
    }
    std::memcpy(nifti.data() + 344, "n+1\0", 4);
    nifti.append(data, bytes);
    std::ofstream(folder + "/ct.nii.gz", std::ios::binary) << deflated(nifti.data(), nifti.size(), true);

    volumes::writeVdb(v, folder + "/ct.vdb", true);
    writeDicomSeries(v, folder + "/dicom");
    std::cout << "wrote 512x512x451 CT (" << static_cast<double>(bytes) / (1024.0 * 1024.0)
              << " MiB of int16) in 6 forms to " << folder << '\n';
}

void load(const std::string& path) {
    const double before = peakResidentMiB();
    const auto start = Clock::now();
    const volumes::LoadedVolume loaded = volumes::loadVolumeWithBricks(path);
    const double seconds = secondsSince(start);
    const double volumeMiB = static_cast<double>(loaded.volume.hu.size() * sizeof(int16_t)) / (1024.0 * 1024.0);
    const double peak = peakResidentMiB();
    std::cout << volumes::volumeFormatName(loaded.format) << "\t" << path << "\tload+bricks " << seconds
              << " s\tvolume " << volumeMiB << " MiB\tpeak RSS " << peak << " MiB (" << before
              << " MiB before loading)\tpeak/volume " << peak / volumeMiB << "\n";
}

void bricks(const std::string& path) {
    const volumes::Volume v = volumes::loadVolume(path);
    std::vector<double> times;
    volumes::BrickMinMax result;
    for (int run = 0; run < 7; ++run) {
        const auto start = Clock::now();
        result = volumes::buildBrickMinMax(v);
        times.push_back(secondsSince(start));
    }
    std::sort(times.begin(), times.end());
    std::cout << "buildBrickMinMax " << v.dims[0] << "x" << v.dims[1] << "x" << v.dims[2] << " -> "
              << result.brickDims[0] << "x" << result.brickDims[1] << "x" << result.brickDims[2] << " bricks: median "
              << times[3] * 1000.0 << " ms, min " << times.front() * 1000.0 << " ms, max " << times.back() * 1000.0
              << " ms (7 runs, " << std::thread::hardware_concurrency() << " threads)\n";
    if (path.size() > 4 && path.substr(path.size() - 4) == ".vdb") {
        // Leaf-based bricks cost the difference between reading with and without them.
        std::vector<double> withBricks, without;
        for (int run = 0; run < 3; ++run) {
            volumes::BrickMinMax fromLeaves;
            auto start = Clock::now();
            volumes::readVdb(path, &fromLeaves);
            withBricks.push_back(secondsSince(start));
            start = Clock::now();
            volumes::readVdb(path);
            without.push_back(secondsSince(start));
        }
        std::sort(withBricks.begin(), withBricks.end());
        std::sort(without.begin(), without.end());
        std::cout << "readVdb: median " << without[1] << " s without bricks, " << withBricks[1]
                  << " s with bricks from leaves (3 runs each, alternated)\n";
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: volumes_bench make FOLDER | load PATH | bricks PATH\n";
        return 2;
    }
    try {
        const std::string command = argv[1];
        if (command == "make") {
            make(argv[2]);
        } else if (command == "load") {
            load(argv[2]);
        } else if (command == "bricks") {
            bricks(argv[2]);
        } else {
            std::cerr << "volumes_bench: unknown command " << command << '\n';
            return 2;
        }
    } catch (const std::exception& e) {
        std::cerr << "volumes_bench: error: " << e.what() << '\n';
        return 1;
    }
    return 0;
}
