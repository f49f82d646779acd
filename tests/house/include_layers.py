#!/usr/bin/env python3
"""The house's rule: a room includes only itself and the rooms below it.

The rooms, lowest first, are listed in LAYERS. A source file belongs to the deepest room whose
folder holds it; an #include "room/..." names the room it reaches into. An include that reaches
a higher room is an upward include, and each one is printed as file:line and fails the check.
Folders above every room (app's tests, benchmarks, fuzzers) may include anything and are not
listed. Includes of generated headers (shaders, embedded files) name no room and are skipped.

Usage: include_layers.py ROOT      check the tree at ROOT
       include_layers.py --self-test   check that the rule catches an upward include
"""
import os
import re
import house_check
import tempfile

# Lowest first. A room may include the rooms before it in this list, and itself.
LAYERS = [
    "volumes",
    "conformal",
    "colon",
    "engine/core",
    "engine/render",
    "engine/output",
    "engine/display",
    "engine/review",
    "engine/sequence",
    "engine/studies",
    "distribution",
    "app",
]
SOURCE_SUFFIXES = (".h", ".hpp", ".cpp", ".cc", ".comp", ".glsl")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def room_of(relative_path):
    """The deepest room whose folder holds relative_path ('/' separated), or None."""
    best = None
    for room in LAYERS:
        if relative_path == room or relative_path.startswith(room + "/"):
            if best is None or len(room) > len(best):
                best = room
    return best


def upward_includes(root):
    """(file, line number, included path, file's room, included room) for every upward include."""
    rank = {room: i for i, room in enumerate(LAYERS)}
    found = []
    for room in LAYERS:
        folder = os.path.join(root, room)
        if not os.path.isdir(folder):
            continue
        for directory, _, names in os.walk(folder):
            for name in sorted(names):
                if not name.endswith(SOURCE_SUFFIXES):
                    continue
                path = os.path.join(directory, name)
                relative = os.path.relpath(path, root).replace(os.sep, "/")
                own = room_of(relative)
                if own != room:
                    continue  # a deeper room's file: checked under that room
                with open(path, encoding="utf-8", errors="replace") as source:
                    for number, line in enumerate(source, 1):
                        match = INCLUDE.match(line)
                        if not match:
                            continue
                        target = room_of(match.group(1))
                        if target is not None and rank[target] > rank[own]:
                            found.append((relative, number, match.group(1), own, target))
    return found


def check(root):
    missing = [room for room in LAYERS if not os.path.isdir(os.path.join(root, room))]
    if missing:
        print("include_layers: rooms missing under %s: %s" % (root, ", ".join(missing)))
        return 1
    found = upward_includes(root)
    for relative, number, included, own, target in found:
        print("%s:%d: includes %s: %s is below %s" % (relative, number, included, own, target))
    if found:
        print("include_layers: %d upward include(s); the rooms, lowest first: %s" % (len(found), ", ".join(LAYERS)))
        return 1
    print("include_layers: no upward include in %d rooms" % len(LAYERS))
    return 0


def self_test():
    """A tree with one upward and one downward include: the rule must report exactly the first."""
    with tempfile.TemporaryDirectory() as root:
        for room in LAYERS:
            os.makedirs(os.path.join(root, room))
        with open(os.path.join(root, "engine/render/ray.cpp"), "w") as f:
            f.write('#include "engine/render/ray.h"\n#include "engine/core/gpu.h"\n#include "volumes/volume.h"\n')
        with open(os.path.join(root, "engine/render/bad.cpp"), "w") as f:
            f.write('#include <vector>\n\n  #include "engine/studies/polyp_check.h"\n#include "shader_spv.h"\n')
        found = upward_includes(root)
        expected = [("engine/render/bad.cpp", 3, "engine/studies/polyp_check.h", "engine/render", "engine/studies")]
        if found != expected:
            print("include_layers self-test: expected %r, found %r" % (expected, found))
            return 1
        if check(root) != 1:
            print("include_layers self-test: the check passed a tree with an upward include")
            return 1
    print("include_layers self-test: the upward include was caught")
    return 0


if __name__ == "__main__":
    house_check.run(check, self_test, __doc__)
