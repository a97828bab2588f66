//! The hecs world, scene files and the frame plan (being built).
