#version 460
// Depth only: the rasteriser writes near / ma; nothing to shade.
void main() {}
