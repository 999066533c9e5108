#!/usr/bin/env python3
"""The pipeline's layering (docs/design.md, "The pipeline"): each stage under src/ includes only
src/common, the public headers of its own or earlier stages, and the stages before it. A public
header belongs to the stage that implements it. The programs (apps/, python/, examples/) include
only public headers and their own files.

    test_layering.py SOURCE_DIR
"""
import os
import re
import sys

STAGES = ["common", "features", "input", "sampling", "voronoi", "clip", "assembly", "weld", "convex",
          "quality", "pipeline", "io", "ensemble"]
# include/froth/X.hpp -> the stage whose code implements it. The data model (the domain, the
# mesh, geometry, errors, the communicator) is common to every stage.
PUBLIC_OWNER = {"error": "common", "geometry": "common", "mesh": "common", "buffer": "common", "communicator": "common",
                "domain": "common", "weld": "weld", "quality": "quality", "validate": "pipeline",
                "partition": "pipeline", "io": "io", "ensemble": "ensemble", "froth": "ensemble"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def includes(path):
    with open(path, encoding="utf-8") as f:
        return INCLUDE.findall(f.read())


def stage_of(include):
    """The stage an include belongs to, or None for a file of the including folder itself."""
    head, _, tail = include.partition("/")
    if head == "froth" and tail.endswith(".hpp"):
        name = tail[:-4]
        if name not in PUBLIC_OWNER:
            return "unknown public header"
        return PUBLIC_OWNER[name]
    return head if head in STAGES else None


def violations(root):
    found = []
    for p in sorted(os.listdir(os.path.join(root, "include", "froth"))):
        if p[:-4] not in PUBLIC_OWNER:
            found.append(f"include/froth/{p}: no stage owns it (add it to PUBLIC_OWNER)")
    for stage in sorted(os.listdir(os.path.join(root, "src"))):
        folder = os.path.join(root, "src", stage)
        if not os.path.isdir(folder):
            continue
        if stage not in STAGES:
            found.append(f"src/{stage}: not a stage of the pipeline (add it to STAGES in order)")
            continue
        for name in sorted(os.listdir(folder)):
            if not name.endswith((".hpp", ".cpp")):
                continue
            for inc in includes(os.path.join(folder, name)):
                to = stage_of(inc)
                if to is None:
                    continue
                if to not in STAGES:
                    found.append(f"src/{stage}/{name} includes {inc}: {to}")
                elif STAGES.index(to) > STAGES.index(stage):
                    found.append(f"src/{stage}/{name} includes {inc}, of the later stage {to}")
    for program in ("apps", "python", "examples"):
        folder = os.path.join(root, program)
        for name in sorted(os.listdir(folder)):
            if not name.endswith((".hpp", ".cpp")):
                continue
            for inc in includes(os.path.join(folder, name)):
                if inc.partition("/")[0] in STAGES:
                    found.append(f"{program}/{name} includes the private header {inc}")
    return found


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    # The checker must be able to fail: a later stage's header included by an earlier one is named.
    assert stage_of("weld/weld_pass.hpp") == "weld" and stage_of("froth/partition.hpp") == "pipeline"
    found = violations(root)
    for v in found:
        print("FAIL:", v)
    if found:
        sys.exit(1)
    print(f"layering: {len(STAGES)} stages, every include points to the same or an earlier stage")


if __name__ == "__main__":
    main()
