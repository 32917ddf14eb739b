//! Scenes: built-in scenes, glTF loading, animation and skinning on the CPU side.
