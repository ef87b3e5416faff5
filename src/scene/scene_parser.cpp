// The scene parser lives in scene_reader.cpp.
