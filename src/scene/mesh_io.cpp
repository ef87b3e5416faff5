// The mesh loader lives in openmesh_io.cpp.
