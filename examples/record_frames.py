#!/usr/bin/python3
"""Record frames of the simulator into numpy: the arm sweeps over a table with a mug and a box,
and every frame's RGB image, object-id mask and depth go into arrays, saved as one .npz.

usage: PYTHONPATH=build/python /usr/bin/python3 examples/record_frames.py [--frames 50]
           [--width 320 --height 240] [--out frames.npz]
"""
import argparse

import numpy as np

from proprio.sim import Scene


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--frames", type=int, default=50)
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=240)
    ap.add_argument("--fps", type=float, default=25.0)
    ap.add_argument("--out", default="frames.npz")
    a = ap.parse_args()

    with Scene([("mug", 0.30, 0.05), ("box", 0.25, -0.12, 0.4)], width=a.width,
               height=a.height) as scene:
        steps = max(1, round(1.0 / a.fps / scene.timestep))
        rgb = np.empty((a.frames, a.height, a.width, 3), np.uint8)
        mask = np.empty((a.frames, a.height, a.width), np.uint16)
        depth = np.empty((a.frames, a.height, a.width), np.float32)
        joints = np.empty((a.frames, 5))
        q0 = scene.arm_joints
        for i in range(a.frames):
            q = q0.copy()
            q[0] = 0.6 * np.sin(2 * np.pi * i / a.frames)  # sweep the base joint
            scene.set_arm_targets(q)
            scene.step(steps)
            frame = scene.render(mask=True, depth=True)
            rgb[i], mask[i], depth[i] = frame["rgb"], frame["mask"], frame["depth"]
            joints[i] = scene.arm_joints
        camera = scene.camera()
        np.savez_compressed(a.out, rgb=rgb, mask=mask, depth=depth, joints=joints,
                            K=camera.K, R=camera.R, t=camera.t, objects=scene.object_names)
    print(f"wrote {a.out}: {a.frames} frames of {a.width} x {a.height}; "
          f"objects in view: {sorted(set(np.unique(mask)) - {0})}")


if __name__ == "__main__":
    main()
