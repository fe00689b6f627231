/* The 2D disk of docs/design.md §7 dropped on a plane (see drop_scene.c, --help). */
#include "drop_scene.h"

int main(int argc, char **argv) { return drop_scene_main(argc, argv, 2); }
