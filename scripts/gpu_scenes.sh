# Sourced by the scripts/gpu_*.sh measurements on the device machine: the shared scenes unpacked
# once into $S (from .device/scenes.tar.xz), the -D defines that point the bench scenes at them at
# 1280×720 in $D, and pyoidn (trimmed to its CPU and CUDA devices, unpacked in /tmp/oidn_site) on
# the Python path.
S=/tmp/scn
[ -d $S/models ] || { mkdir -p $S && tar -xJf .device/scenes.tar.xz -C $S; }
export PYTHONPATH=/tmp/oidn_site:$PYTHONPATH
D="-D resx=1280 -D resy=720 -D models_dir=$S/models -D sponza_dir=$S/sponza-dabrovic -D showcase_dir=$S/cbox -D dining_dir=$S/dining-room"
