// A truncated geometry (tests/bad/unreadable_mesh.toml): gmsh cannot parse it.
Box(1) = {0, 0, 0, 1, 1
