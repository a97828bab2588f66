//! The scan-line rasterizer and its shading modes (being built).
