"""Exports rayproc scenes to Blender Cycles and measures Cycles against rayproc.

scene_reader: rayproc JSON scene -> a flat plan (world-space objects, materials, lights, camera).
blender_script: plan -> a self-contained Blender Python script that builds and renders it.
runner: runs Blender, reads Cycles' own timings, compares images with `rayproc diff`.
See docs/peer-cycles.md.
"""
