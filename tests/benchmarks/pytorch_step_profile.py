#!/usr/bin/env python3
"""Where PyTorch's training step of the shared ResNet-18 spends its time, from Python.

The counterpart of resnet18_step_profile: pytorch_anchors.py's model, batch, optimiser and
threads, a few steps after warm-up under torch.profiler, operators by self time and first input
shape. Needs Debian's python3-torch (tools/bench_setup.sh).

    /usr/bin/python3 pytorch_step_profile.py CHANNELS MEL_BINS FRAMES [STEPS] [ROWS]
"""
import os
import sys
import time

from pytorch_anchors import BATCH, resnet_training


def main():
    try:
        if not 4 <= len(sys.argv) <= 6:
            raise ValueError("wrong number of arguments")
        channels, mel_bins, frames = (int(value) for value in sys.argv[1:4])
        steps = int(sys.argv[4]) if len(sys.argv) > 4 else 3
        rows = int(sys.argv[5]) if len(sys.argv) > 5 else 30
        if min(channels, steps, rows) < 1 or min(mel_bins, frames) < 8:
            raise ValueError("out of range")
    except ValueError as error:
        print(f"pytorch_step_profile.py: {error}: expected CHANNELS MEL_BINS FRAMES [STEPS] [ROWS], whole numbers: "
              "CHANNELS, STEPS and ROWS >= 1, MEL_BINS and FRAMES >= 8", file=sys.stderr)
        return 2
    try:
        import torch
    except ImportError as error:
        print(f"pytorch_step_profile.py: {error}: run it with Debian's /usr/bin/python3 after "
              "tools/bench_setup.sh", file=sys.stderr)
        return 1
    torch.set_num_threads(os.cpu_count() or 1)  # as pytorch_anchors.py
    encoder, _, train_step = resnet_training(torch, channels, mel_bins, frames)
    encoder.train()
    train_step()
    train_step()
    start = time.perf_counter()
    for _ in range(steps):
        train_step()
    unprofiled_ms = (time.perf_counter() - start) * 1000 / steps
    with torch.profiler.profile(activities=[torch.profiler.ProfilerActivity.CPU], record_shapes=True) as profile:
        for _ in range(steps):
            train_step()
    print(f"training step {channels}x{mel_bins}x{frames}, batch {BATCH}, {torch.get_num_threads()} threads: "
          f"{unprofiled_ms:.1f} ms unprofiled (totals below are over {steps} steps)")
    print(profile.key_averages(group_by_input_shape=True).table(sort_by="self_cpu_time_total", row_limit=rows))
    print(profile.key_averages().table(sort_by="self_cpu_time_total", row_limit=rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
