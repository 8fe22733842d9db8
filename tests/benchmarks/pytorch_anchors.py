#!/usr/bin/env python3
"""PyTorch's and torchaudio's rates on this machine, measured in the same `bench` run as ours.

Runs the work of resnet18_benchmark and log_mel_benchmark the way a Python reimplementation
would (eager PyTorch, batch norm unfused, torchaudio's transforms) with the same shapes, batch,
model, optimiser, thread count and timing rule, and writes one JSON file of rates keyed by the
benchmarks' names. The C++ programs read it (FSCIL_PYTORCH_ANCHORS) and print ours, theirs and
the ratio. Needs Debian's python3-torch and python3-torchaudio (tools/bench_setup.sh).

    python3 pytorch_anchors.py --out FILE [--filter SUBSTRING]
"""
import argparse
import json
import os
import sys
import tempfile
import time

BATCH, CLASSES = 128, 60
SEGMENTS = 64  # log_mel_benchmark's batch

# name: (channels, mel_bins, frames, timing); timing as in resnet18_benchmark.cpp: a minimum
# time in seconds, or a fixed number of iterations for the shapes where one step takes seconds.
RESNET_SHAPES = {
    "haptex_5x64x24": (5, 64, 24, {"min_time": 2.0}),
    "lmt108_3x64x493": (3, 64, 493, {"train_iterations": 3, "infer_iterations": 5}),
    "ls100_3x128x178": (3, 128, 178, {"train_iterations": 3, "infer_iterations": 5}),
    "ns100_3x128x63": (3, 128, 63, {"train_iterations": 5, "infer_iterations": 10}),
}

# preset: (channels, length, sample_rate, n_fft, hop, n_mels, center), datasets/log_mel_settings.cpp
LOG_MEL_PRESETS = {
    "haptex": (5, 500, 1000, 128, 16, 64, False),
    "lmt108": (3, 8000, 10000, 128, 16, 64, False),
    "ls100": (3, 32000, 16000, 400, 180, 128, True),
    "ns100": (3, 64000, 16000, 2048, 1024, 128, True),
}


def timed(step, min_time=None, iterations=None):
    """Calls step once to warm up, then times it; returns (iterations, seconds)."""
    step()
    done, start = 0, time.perf_counter()
    while True:
        step()
        done += 1
        elapsed = time.perf_counter() - start
        if (iterations is not None and done >= iterations) or (min_time is not None and elapsed >= min_time):
            return done, elapsed


def resnet18(torch, channels, mel_bins):
    """methods/common/resnet18.cpp as PITS-SC's Python code builds it: bn0 over Mel bins, then
    torchvision's ResNet-18 with stage widths 64, 128, 256, 256 and global average pooling."""
    nn = torch.nn

    class Block(nn.Module):
        def __init__(self, inp, out, stride):
            super().__init__()
            self.conv1 = nn.Conv2d(inp, out, 3, stride, 1, bias=False)
            self.bn1 = nn.BatchNorm2d(out)
            self.conv2 = nn.Conv2d(out, out, 3, 1, 1, bias=False)
            self.bn2 = nn.BatchNorm2d(out)
            self.downsample = None
            if stride != 1 or inp != out:
                self.downsample = nn.Sequential(nn.Conv2d(inp, out, 1, stride, bias=False), nn.BatchNorm2d(out))

        def forward(self, x):
            out = torch.relu(self.bn1(self.conv1(x)))
            out = self.bn2(self.conv2(out))
            return torch.relu(out + (self.downsample(x) if self.downsample is not None else x))

    class Encoder(nn.Module):
        def __init__(self):
            super().__init__()
            self.bn0 = nn.BatchNorm2d(mel_bins)
            self.conv1 = nn.Conv2d(channels, 64, 7, 2, 3, bias=False)
            self.bn1 = nn.BatchNorm2d(64)
            blocks, inp = [], 64
            for stage, width in enumerate((64, 128, 256, 256)):
                blocks += [Block(inp, width, 1 if stage == 0 else 2), Block(width, width, 1)]
                inp = width
            self.stages = nn.Sequential(*blocks)

        def forward(self, x):
            x = self.bn0(x.transpose(1, 2)).transpose(1, 2)
            x = torch.max_pool2d(torch.relu(self.bn1(self.conv1(x))), 3, 2, 1)
            return torch.flatten(torch.nn.functional.adaptive_avg_pool2d(self.stages(x), 1), 1)

    return Encoder()


def resnet_training(torch, channels, mel_bins, frames):
    """The encoder, one batch of random maps, and a training step on it: a cosine classifier at
    temperature 16, Nesterov SGD (methods/common/encoder_step.cpp)."""
    F = torch.nn.functional
    torch.manual_seed(1)
    encoder = resnet18(torch, channels, mel_bins)
    weight = torch.nn.Parameter(torch.randn(CLASSES, 256))
    optimizer = torch.optim.SGD(list(encoder.parameters()) + [weight], lr=0.1, momentum=0.9,
                                nesterov=True, weight_decay=5e-4)
    features = torch.randn(BATCH, channels, mel_bins, frames)
    labels = torch.randint(CLASSES, (BATCH,))

    def train_step():
        optimizer.zero_grad()
        logits = 16.0 * F.normalize(encoder(features), dim=1) @ F.normalize(weight, dim=1).t()
        F.cross_entropy(logits, labels).backward()
        optimizer.step()

    return encoder, features, train_step


def resnet_rates(torch, name, channels, mel_bins, frames, timing):
    encoder, features, train_step = resnet_training(torch, channels, mel_bins, frames)
    encoder.train()
    steps, seconds = timed(train_step, timing.get("min_time"), timing.get("train_iterations"))
    rates = {f"train/{name}": BATCH * steps / seconds}

    encoder.eval()
    with torch.no_grad():
        steps, seconds = timed(lambda: encoder(features), timing.get("min_time"), timing.get("infer_iterations"))
    rates[f"infer/{name}"] = BATCH * steps / seconds
    return rates


def log_mel_rate(torch, torchaudio, channels, length, sample_rate, n_fft, hop, n_mels, center):
    mel = torchaudio.transforms.MelSpectrogram(sample_rate=sample_rate, n_fft=n_fft, win_length=n_fft,
                                               hop_length=hop, n_mels=n_mels, center=center,
                                               pad_mode="reflect", power=2.0, norm=None, mel_scale="htk")
    to_db = torchaudio.transforms.AmplitudeToDB(stype="power", top_db=None)
    torch.manual_seed(1)
    signals = torch.randn(SEGMENTS, channels, length)
    with torch.no_grad():
        steps, seconds = timed(lambda: to_db(mel(signals)), min_time=1.0)
    return SEGMENTS * steps / seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="JSON file of rates to write")
    parser.add_argument("--filter", default="", help="measure only figures whose name contains this")
    args = parser.parse_args()
    try:
        import torch
        import torchaudio
    except ImportError as error:
        print(f"pytorch_anchors.py: {error}: run tools/bench_setup.sh to install Debian's "
              "python3-torch and python3-torchaudio", file=sys.stderr)
        return 1
    threads = os.cpu_count() or 1  # as tests/benchmarks/torch_benchmark_main.cpp
    torch.set_num_threads(threads)

    rates = {}
    for name, (channels, mel_bins, frames, timing) in RESNET_SHAPES.items():
        if args.filter in f"train/{name}" or args.filter in f"infer/{name}":
            rates.update(resnet_rates(torch, name, channels, mel_bins, frames, timing))
    for name, preset in LOG_MEL_PRESETS.items():
        if args.filter in f"log_mel/{name}":
            rates[f"log_mel/{name}"] = log_mel_rate(torch, torchaudio, *preset)
    for figure, rate in rates.items():
        print(f"pytorch_anchors: {figure:28} {rate:10.1f} /s")

    record = {"torch": torch.__version__, "torchaudio": torchaudio.__version__, "threads": threads,
              "unit": "samples (log_mel: segments) per second", "rates": rates}
    folder = os.path.dirname(os.path.abspath(args.out))
    os.makedirs(folder, exist_ok=True)
    with tempfile.NamedTemporaryFile("w", dir=folder, delete=False, suffix=".tmp") as file:
        json.dump(record, file, indent=1)
    os.replace(file.name, args.out)  # whole or not at all: the benchmarks never read half a file
    return 0


if __name__ == "__main__":
    sys.exit(main())
