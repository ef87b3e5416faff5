// Height tables live in height_source.cpp.
