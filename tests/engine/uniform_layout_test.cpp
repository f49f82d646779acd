// The ray caster's uniform block: every member's offset in the C++ struct equals its offset in
// the compiled shader, as glslang's reflection of raycast.comp reports it (generated at build
// time), and the block's size matches. A member renamed, reordered or retyped on one side only
// fails here, not as a wrong picture.
#include <cstddef>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include "host_device.h"

namespace {

#define CVC_MEMBER(name) {"u." #name, offsetof(shaders::RaycastUniforms, name)}

// Every member of the uniform block that the shader reads: all but the trailing padding, which
// the block size below covers.
const std::map<std::string, std::size_t> kCppOffsets = {
    CVC_MEMBER(eyeMm),           CVC_MEMBER(nearMm),         CVC_MEMBER(wallOriginMm),
    CVC_MEMBER(stepMm),          CVC_MEMBER(wallUMm),        CVC_MEMBER(isoHu),
    CVC_MEMBER(wallVMm),         CVC_MEMBER(speedBoundCosReach), CVC_MEMBER(wallNormal),
    CVC_MEMBER(maxSteps),        CVC_MEMBER(mapCentreMm),    CVC_MEMBER(minStepMm),
    CVC_MEMBER(caveToVolume0),   CVC_MEMBER(maxStepMm),      CVC_MEMBER(caveToVolume1),
    CVC_MEMBER(radiansPerPixel), CVC_MEMBER(caveToVolume2),  CVC_MEMBER(opacityToStop),
    CVC_MEMBER(boxMinMm),        CVC_MEMBER(transferFirstHu), CVC_MEMBER(boxMaxMm),
    CVC_MEMBER(transferIndexPerHu), CVC_MEMBER(texFromMmScale), CVC_MEMBER(transferReferenceStepMm),
    CVC_MEMBER(texFromMmOffset), CVC_MEMBER(transferHalfEntry), CVC_MEMBER(volumeDims),
    CVC_MEMBER(skipCellVoxels),  CVC_MEMBER(invSpacingMm),   CVC_MEMBER(lightFalloffPerMm2),
    CVC_MEMBER(roughness),       CVC_MEMBER(fresnelF0),      CVC_MEMBER(ambient),         CVC_MEMBER(chordReachMm),
    CVC_MEMBER(imageSize),       CVC_MEMBER(transferVisibleFromHu), CVC_MEMBER(transferVisibleToHu),
    CVC_MEMBER(jitterSeed),      CVC_MEMBER(isLookingInEveryTile),
};

#undef CVC_MEMBER

/// The number glslang writes right after `key` in `line` ("offset 16,"), if `key` is there.
/// Parsed by hand: GCC 12's <regex> draws -Wmaybe-uninitialized warnings at -O1.
std::optional<long> numberAfter(const std::string& line, const std::string& key) {
    const std::size_t at = line.find(key);
    if (at == std::string::npos) return std::nullopt;
    const char* start = line.c_str() + at + key.size();
    char* end = nullptr;
    const long value = std::strtol(start, &end, 10);
    if (end == start || *end != ',') return std::nullopt;
    return value;
}

TEST(UniformLayout, EveryOffsetEqualsTheCompiledShadersReflection) {
    std::ifstream in(CVC_RAYCAST_REFLECTION);
    ASSERT_TRUE(in) << "cannot read " << CVC_RAYCAST_REFLECTION;
    // Lines such as "u.eyeMm: offset 0, type ..." and "Uniforms: offset -1, type ..., size 256, ...".
    std::map<std::string, long> reflected;
    long blockSize = 0;
    for (std::string line; std::getline(in, line);) {
        const std::size_t colon = line.find(": offset ");
        if (colon == std::string::npos) continue;
        const std::string name = line.substr(0, colon);
        if (name.rfind("u.", 0) == 0 && name.size() > 2) {
            if (const auto offset = numberAfter(line, ": offset ")) reflected[name] = *offset;
        } else if (name == "Uniforms") {
            if (const auto size = numberAfter(line, ", size ")) blockSize = *size;
        }
    }
    ASSERT_FALSE(reflected.empty()) << "no uniform members in " << CVC_RAYCAST_REFLECTION;
    EXPECT_EQ(blockSize, static_cast<long>(sizeof(shaders::RaycastUniforms)));
    for (const auto& [name, offset] : reflected) {
        const auto found = kCppOffsets.find(name);
        ASSERT_NE(found, kCppOffsets.end()) << name << " is in the shader but not in the C++ table";
        EXPECT_EQ(static_cast<long>(found->second), offset) << name << ": C++ offset " << found->second << ", shader offset " << offset;
    }
    for (const auto& [name, offset] : kCppOffsets) {
        EXPECT_TRUE(reflected.count(name)) << name << " (C++ offset " << offset << ") is not read by the shader";
    }
}

}  // namespace
