#!/usr/bin/env python3
"""Checks that every #include <tessera/FOLDER/...> in include/tessera/ and src/ points down the
layer order below (README.md, "Layout"): a folder may include its own headers and those of the
folders before it, never those after it, so no two folders include each other (no cycles).
src/cli/ (the command) sits above everything. Exits 1 naming each upward include."""
import os
import re
import sys

# Lowest first; each folder's job is in README.md, "Layout".
LAYERS = ["errors", "math", "state", "buffers", "io", "texture", "shaders", "scene", "shading",
          "raster", "compute", "gbuffer", "culling", "raytrace", "frame", "inspect", "techniques"]


def main() -> int:
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    rank = {name: i for i, name in enumerate(LAYERS)}
    problems = []
    for tree in ("include/tessera", "src"):
        base = os.path.join(root, tree)
        for folder, _, files in os.walk(base):
            for name in sorted(files):
                if not name.endswith((".h", ".cpp")):
                    continue
                path = os.path.join(folder, name)
                layer = os.path.relpath(path, base).split(os.sep)[0]
                if layer == "cli" or layer == name:
                    continue
                if layer not in rank:
                    problems.append(f"{os.path.relpath(path, root)}: folder '{layer}' has no place in LAYERS")
                    continue
                with open(path, encoding="utf-8") as f:
                    for number, line in enumerate(f, 1):
                        m = re.match(r'\s*#\s*include\s*[<"]tessera/([a-z_]+)/', line)
                        if not m:
                            continue
                        target = m.group(1)
                        if target not in rank:
                            problems.append(f"{os.path.relpath(path, root)}:{number}: includes unknown folder '{target}'")
                        elif rank[target] > rank[layer]:
                            problems.append(f"{os.path.relpath(path, root)}:{number}: {layer} includes {target}, a layer above it")
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} include(s) against the layer order: {' < '.join(LAYERS)}")
        return 1
    print(f"every include points down: {' < '.join(LAYERS)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
