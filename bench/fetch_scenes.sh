#!/usr/bin/env bash
# Fetches real models made by others from Debian 12 packages into bench/scenes/ (git-ignored),
# then writes the benchmark scenes from them (bench/make_scenes.py -> bench/scenes/generated/).
# The data packages are only downloaded (apt-get download) and unpacked with dpkg-deb -x into
# bench/models/, never installed. Each model's folder gets its package's copyright file (and the
# model's own licence where the package ships one). Models tinygltf or our OBJ loader cannot read
# (OFF, IFC) are converted to .glb with `assimp export`. Idempotent: what exists is not redone.
set -euo pipefail
cd "$(dirname "$0")/.."

# Tools only (like scripts/setup.sh: installs what is missing, nothing else).
tools=(assimp-utils unzip python3-numpy)
missing=()
for p in "${tools[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
if [ ${#missing[@]} -gt 0 ]; then
  echo "fetch_scenes: installing ${missing[*]}"
  $sudo_cmd apt-get -o DPkg::Lock::Timeout=600 update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends "${missing[@]}"
fi

# apt-get download needs the package lists, which a fresh container may not have yet.
apt-cache show glmark2-data >/dev/null 2>&1 || $sudo_cmd apt-get -o DPkg::Lock::Timeout=600 update -qq

models=bench/models scenes=bench/scenes
mkdir -p "$models/debs" "$scenes"

# Downloads and unpacks one data package into bench/models/PKG/ (once).
unpack() {
  local pkg=$1
  [ -d "$models/$pkg/usr" ] && return 0
  if ! ls "$models/debs/${pkg}"_*.deb >/dev/null 2>&1; then
    echo "fetch_scenes: downloading $pkg"
    # apt-get download writes into the working directory; _apt cannot write there as root, which
    # only costs a warning about the unsandboxed download.
    (cd "$models/debs" && apt-get download "$pkg" 2>&1 | grep -v "unsandboxed" || true)
    ls "$models/debs/${pkg}"_*.deb >/dev/null 2>&1 || { echo "fetch_scenes: could not download $pkg" >&2; exit 1; }
  fi
  mkdir -p "$models/$pkg.tmp"
  dpkg-deb -x "$models/debs/${pkg}"_*.deb "$models/$pkg.tmp"
  mv "$models/$pkg.tmp" "$models/$pkg"
}

# Copies the package's licence file beside a model (as copyright.PKG).
licence() {  # folder pkg
  local doc="$models/$2/usr/share/doc/$2/copyright"
  [ -f "$1/copyright.$2" ] && return 0
  [ -f "$doc" ] || { echo "fetch_scenes: $2 has no $doc" >&2; exit 1; }
  cp "$doc" "$1/copyright.$2"
}

# Converts SRC to DEST.glb with assimp when DEST does not exist yet.
convert() {
  [ -f "$2" ] && return 0
  echo "fetch_scenes: assimp export $(basename "$1") -> $2"
  assimp export "$1" "$2.tmp.glb" -fglb2 >/dev/null
  mv "$2.tmp.glb" "$2"
}

# Stanford Bunny, the full scan (69,666 triangles) as shipped with glmark2; our OBJ loader reads it.
unpack glmark2-data
mkdir -p "$scenes/bunny"
[ -f "$scenes/bunny/bunny.obj" ] || cp "$models/glmark2-data/usr/share/glmark2/models/bunny.obj" "$scenes/bunny/"
licence "$scenes/bunny" glmark2-data

# Stanford Armadillo, decimated to 52K triangles, in CGAL's example data (OFF -> glb). libcgal-demo's
# doc folder is a link to libcgal-dev's, so the licence comes from libcgal-dev (downloaded only for it).
unpack libcgal-demo
unpack libcgal-dev
mkdir -p "$scenes/armadillo"
if [ ! -f "$scenes/armadillo/armadillo.glb" ]; then
  data=$(find "$models/libcgal-demo/usr/share/doc" -name data.tar.gz -path "*libcgal-dev*" | head -n 1)
  tar -xzf "$data" -C "$models/libcgal-demo" data/meshes/armadillo.off
  convert "$models/libcgal-demo/data/meshes/armadillo.off" "$scenes/armadillo/armadillo.glb"
fi
licence "$scenes/armadillo" libcgal-dev

# Two-cylinder engine (CAD, 121K triangles, some of zero area) and the FZK-Haus building (IFC -> glb)
# from assimp's test models.
unpack assimp-testmodels
am=$models/assimp-testmodels/usr/share/assimp/models
mkdir -p "$scenes/engine" "$scenes/fzk-haus"
[ -f "$scenes/engine/2CylinderEngine.glb" ] || cp "$am/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb" "$scenes/engine/"
licence "$scenes/engine" assimp-testmodels
convert "$am/IFC/AC14-FZK-Haus.ifc" "$scenes/fzk-haus/AC14-FZK-Haus.glb"
[ -f "$scenes/fzk-haus/AC14-FZK-Haus.source.txt" ] || cp "$am/IFC/AC14-FZK-Haus.source.txt" "$scenes/fzk-haus/"
licence "$scenes/fzk-haus" assimp-testmodels

# A wrought-iron fence (thin bars, 19K triangles) from Sweet Home 3D's CC-0 BlendSwap catalogue,
# a zip archive; the OBJ loads as it is (its .mtl and the model's own licence page come along).
unpack sweethome3d-furniture
mkdir -p "$scenes/fence"
if [ ! -f "$scenes/fence/fence.obj" ]; then
  unzip -o -q -j "$models/sweethome3d-furniture/usr/share/sweethome3d/furniture/BlendSwap-CC-0.sh3f" \
    'blendswap-cc-0/fence/*' -d "$scenes/fence"
fi
licence "$scenes/fence" sweethome3d-furniture

# Models of kinds the project's own scenes do not have (issue 17), used as they are, without a
# ground quad. A Japanese maple (166K faces of leaves and twigs) from Sweet Home 3D's Scopia
# catalogue (CC-BY 3.0).
mkdir -p "$scenes/maple"
if [ ! -f "$scenes/maple/japaneseMaple.obj" ]; then
  unzip -o -q -j "$models/sweethome3d-furniture/usr/share/sweethome3d/furniture/Scopia.sh3f" \
    'scopia/japaneseMaple/*' -d "$scenes/maple"
fi
licence "$scenes/maple" sweethome3d-furniture

# Alpha-tested content (issue 41): Scopia's football goal (CC-BY 3.0), whose net is a few quads cut
# out by their texture's alpha (map_d); bench/make_scenes.py stands it on a ground (goal_stage.obj).
mkdir -p "$scenes/goal"
if [ ! -f "$scenes/goal/big-football-goal.obj" ]; then
  unzip -o -q -j "$models/sweethome3d-furniture/usr/share/sweethome3d/furniture/Scopia.sh3f" \
    'scopia/big-football-goal/*' -d "$scenes/goal"
fi
licence "$scenes/goal" sweethome3d-furniture
# ... and its bush (CC-BY 3.0): leaves are cards cut out by leaf.png's alpha (map_d).
mkdir -p "$scenes/bush"
if [ ! -f "$scenes/bush/bush.obj" ]; then
  unzip -o -q -j "$models/sweethome3d-furniture/usr/share/sweethome3d/furniture/Scopia.sh3f" \
    'scopia/bush/*' -d "$scenes/bush"
fi
licence "$scenes/bush" sweethome3d-furniture

# Two ships from FlightGear's models (GPL-2+): the carrier USS Harry S. Truman (99K faces, masts,
# antennas, deck markings, textured) and a sailing boat with rigging (AC3D -> glb).
unpack flightgear-data-models
fg=$models/flightgear-data-models/usr/share/games/flightgear/Models
mkdir -p "$scenes/truman" "$scenes/sailboat"
convert "$fg/Geometry/Nimitz/truman.ac" "$scenes/truman/truman.glb"
cp -n "$fg/Geometry/Nimitz/"*.png "$scenes/truman/"  # its textures (20 MB of PNG; its SGI .rgb ones are not read)
convert "$fg/Maritime/Civilian/SailBoatUnderSail.ac" "$scenes/sailboat/SailBoatUnderSail.glb"
licence "$scenes/truman" flightgear-data-models
licence "$scenes/sailboat" flightgear-data-models

# Two brush-built game levels from OpenArena 0.8.1's maps (GPL-2): oasago2 (41K triangles) and
# ctf_inyard (29K), Quake III BSPs read by bench/make_scenes.py.
unpack openarena-081-maps
mkdir -p "$scenes/openarena"
for map in oasago2 ctf_inyard; do
  [ -f "$scenes/openarena/$map.bsp" ] ||
    unzip -o -q -j "$models/openarena-081-maps/usr/share/games/openarena/baseoa/pak1-maps.pk3" "maps/$map.bsp" -d "$scenes/openarena"
done
licence "$scenes/openarena" openarena-081-maps

# Staged, subdivided, instanced and stability scenes (Debian's python3, which has numpy).
/usr/bin/python3 bench/make_scenes.py "$scenes"
echo "fetch_scenes: models in $scenes/, generated scenes in $scenes/generated/"
