# Sourced by this stop's run scripts on the device machine: the bundle's prelude, the extras
# (extras.sh) on the path, the plugins where the installed package would map them, and the
# bench scenes' parameters ($D) and files ($S).
set -uo pipefail
source .device/prelude.sh
export PYTHONPATH="/tmp/extra:$PYTHONPATH"
ln -sfn ../plugins hybrid_integrator/plugins
D="-D resx=1280 -D resy=720 -D models_dir=/tmp/scn/models -D sponza_dir=/tmp/scn/sponza-dabrovic -D showcase_dir=/tmp/scn/cbox -D dining_dir=/tmp/scn/dining-room"
S="${SCENES:-scenes/armadillo_glass.xml scenes/showcase.xml scenes/sponza_mirror.xml scenes/dining_room.xml scenes/many_objects.xml}"  # $SCENES: a subset
