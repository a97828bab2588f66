//! Triangle meshes: OBJ loading, face and vertex normals that keep creases, tangents and analytic primitives (being built).
