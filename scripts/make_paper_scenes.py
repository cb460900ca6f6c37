"""Write the paper-scale benchmark scenes (issue 5) as project XML in ``scenes/``.

The meshes and textures stay where they are (``../shared/scenes/`` beside the checkout); each
scene takes the folder that holds them as a parameter, so a user points it at their own copy:

    mi.load_file("scenes/sponza_mirror.xml", sponza_dir="/data/sponza-dabrovic")
    hybrid bench scenes/sponza_mirror.xml -D sponza_dir=/data/sponza-dabrovic

Every scene is 1280×720 by default (the paper's resolution, §8) and takes ``$integrator``
(default ``path``), ``$spp``, ``$resx``, ``$resy`` and ``$max_depth``.

- ``sponza_mirror.xml``: Dabrović's Sponza atrium (the paper used Crytek's), its floor a smooth
  plastic coat over the floor texture: reflections (paper Fig. 5a);
- ``showcase.xml``: the coloured-glass showcase (tinted glass bunny, teapot, spheres, a mirror
  sphere): coloured shadows and refraction (Fig. 5b);
- ``dining_room.xml``: Bitterli's dining room, the paper's Brigade comparison scene (Fig. 5d);
- ``armadillo_glass.xml`` is written by hand: the ≈400k-triangle Armadillo in glass (Fig. 5c).

    python scripts/make_paper_scenes.py
"""
from __future__ import annotations

import argparse
import os
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "scenes"


def _parametrize(source: Path, target: Path, param: str, edit=None, defaults: dict | None = None) -> None:
    """Copy ``source`` to ``target`` with every file name prefixed by ``$param`` (default: the
    source folder, relative to ``target``), ``$integrator`` as the integrator, then ``edit(root)``."""
    tree = ET.parse(source)
    root = tree.getroot()
    for node in root.iter():
        if node.get("name") == "filename":
            node.set("value", f"${param}/{node.get('value')}")
    for node in root.iter("integrator"):
        node.set("type", "$integrator")
    relative = os.path.relpath(source.parent, target.parent)
    existing = {d.get("name"): d for d in root.findall("default")}
    values = {param: relative, "integrator": "path", **(defaults or {})}
    for k, (name, value) in enumerate(values.items()):
        if name in existing:
            existing[name].set("value", value)
        else:
            root.insert(k, ET.Element("default", {"name": name, "value": value}))
    if edit is not None:
        edit(root)
    ET.indent(tree, space="    ")
    header = f"<!-- Written by scripts/make_paper_scenes.py from {os.path.relpath(source, ROOT.parent)}; "\
             f"${param}: the folder of its meshes and textures. -->\n"
    target.write_text(header + ET.tostring(root, encoding="unicode") + "\n")


def _mirror_floor(root: ET.Element) -> None:
    """Sponza's floor: a smooth plastic coat over its diffuse floor texture (delta reflection)."""
    floor = next(s for s in root.iter("shape") if s.get("id") == "floors-lib_0")
    ref = floor.find("ref[@name='bsdf']")
    diffuse = next(b for b in root.iter("bsdf") if b.get("id") == ref.get("id"))
    texture = diffuse.find("ref[@name='reflectance']").get("id")
    floor.remove(ref)
    coat = ET.SubElement(floor, "bsdf", {"type": "plastic"})
    ET.SubElement(coat, "ref", {"name": "diffuse_reflectance", "id": texture})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--shared", type=Path, default=SHARED, help="the reference scenes (../shared/scenes)")
    args = parser.parse_args()
    out = ROOT / "scenes"
    _parametrize(args.shared / "sponza-dabrovic/scene.xml", out / "sponza_mirror.xml", "sponza_dir", _mirror_floor)
    _parametrize(args.shared / "cbox/showcase_coloured_glass.xml", out / "showcase.xml", "showcase_dir",
                 defaults={"resx": "1280", "resy": "720"})
    _parametrize(args.shared / "dining-room/scene.xml", out / "dining_room.xml", "dining_dir")
    print("wrote", ", ".join(f"scenes/{n}" for n in ("sponza_mirror.xml", "showcase.xml", "dining_room.xml")))


if __name__ == "__main__":
    main()
