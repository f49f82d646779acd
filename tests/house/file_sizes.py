#!/usr/bin/env python3
"""The house's size limits: no source or documentation file over 800 lines, no command of app/
over 300, and the benchmark page under 300, so that each file stays one job a reader can hold.

Build folders, outputs, third-party and data files are not looked at. Each file over its limit
is printed with its line count and fails the check.

Usage: file_sizes.py ROOT          check the tree at ROOT
       file_sizes.py --self-test   check that a file over a limit is caught
"""
import fnmatch
import os
import house_check
import tempfile

CHECKED_SUFFIXES = (".h", ".hpp", ".cpp", ".cc", ".comp", ".glsl", ".py", ".sh", ".md", ".js", ".css", ".html",
                    ".txt", ".cmake")
SKIPPED_FOLDERS = {".git", "out"}
# The most specific pattern first: a file takes the first limit whose pattern it matches.
LIMITS = [
    ("app/*.cpp", 300),
    ("docs/benchmarks.md", 300),
    ("*", 800),
]


def limit_of(relative_path):
    for pattern, limit in LIMITS:
        if fnmatch.fnmatchcase(relative_path, pattern):
            return limit
    return None


def files_over(root):
    found = []
    for directory, folders, names in os.walk(root):
        folders[:] = sorted(f for f in folders if f not in SKIPPED_FOLDERS and not f.startswith("build"))
        for name in sorted(names):
            if not name.endswith(CHECKED_SUFFIXES):
                continue
            path = os.path.join(directory, name)
            relative = os.path.relpath(path, root).replace(os.sep, "/")
            with open(path, encoding="utf-8", errors="replace") as text:
                lines = sum(1 for _ in text)
            limit = limit_of(relative)
            if limit is not None and lines > limit:
                found.append((relative, lines, limit))
    return found


def check(root):
    found = files_over(root)
    for relative, lines, limit in found:
        print("%s: %d lines, over its limit of %d" % (relative, lines, limit))
    if found:
        print("file_sizes: %d file(s) over their limit" % len(found))
        return 1
    print("file_sizes: every file within its limit")
    return 0


def self_test():
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "app"))
        os.makedirs(os.path.join(root, "build", "app"))
        with open(os.path.join(root, "app", "long_command.cpp"), "w") as f:
            f.write("int x;\n" * 301)
        with open(os.path.join(root, "app", "short_command.cpp"), "w") as f:
            f.write("int x;\n" * 300)
        with open(os.path.join(root, "build", "app", "generated.cpp"), "w") as f:
            f.write("int x;\n" * 5000)
        found = files_over(root)
        if found != [("app/long_command.cpp", 301, 300)]:
            print("file_sizes self-test: expected only app/long_command.cpp, found %r" % found)
            return 1
    print("file_sizes self-test: the long file was caught")
    return 0


if __name__ == "__main__":
    house_check.run(check, self_test, __doc__)
