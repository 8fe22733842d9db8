"""What a Python user sees of our HDF5 files with h5py: names and numbers, not bytes.

    h5py_read_test.py FSCIL_BENCH WORK
Writes a segment cache (a smoke run on simtex-mini) and a logmel output, then reads both.
"""
import pathlib
import shutil
import subprocess
import sys

import h5py
import numpy as np

bench, work = sys.argv[1], pathlib.Path(sys.argv[2])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)

subprocess.run([bench, "--methods", "prototype", "--dataset", "simtex-mini", "--profile", "smoke", "--quiet",
                "--no-stage-cache", "--cache-dir", str(work / "cache"), "--out", str(work / "run")],
               check=True, stdout=subprocess.DEVNULL)
(cache,) = (work / "cache").glob("simtex-mini-*.h5")
with h5py.File(cache, "r") as f:
    attrs = {key: f.attrs[key] for key in f.attrs}
    assert attrs["format_version"] == "4", attrs
    assert attrs["dataset"] == "simtex-mini", attrs
    assert float(attrs["sample_rate"]) > 0, attrs
    assert int(attrs["segment_length"]) == f["signals"].shape[2], attrs
    assert "mel" in attrs["front_end"], attrs["front_end"]
    classes = f["class_names"].asstr()[:]
    channels = f["channel_names"].asstr()[:]
    assert len(classes) == 20 and all(isinstance(name, str) and name for name in classes), classes
    assert len(channels) == f["signals"].shape[1], channels
    signals = f["signals"]
    assert signals.dtype == np.float32 and signals.ndim == 3, signals
    assert f["class_index"].shape == (signals.shape[0],)
    contexts = f["contexts"]
    columns = list(contexts.attrs["columns"])
    assert all(isinstance(c, str) for c in columns), columns  # names, not bytes
    assert contexts.dtype == np.float64 and contexts.shape == (len(f["recording_ids"]), len(columns)), contexts
    assert int(attrs["context_count"]) == len(columns) > 0, columns
    recordings = f["recording_ids"].asstr()[:]
    print(f"{cache.name}: {signals.shape[0]} segments {signals.shape[1:]} of {len(classes)} classes "
          f"({classes[0]}, ...), channels {list(channels)}, contexts {contexts.shape} {columns}, "
          f"recordings {recordings[0]}, ...; attributes {sorted(attrs)}")

with h5py.File(work / "signal.h5", "w") as f:
    f["signal"] = np.sin(np.arange(2 * 4000, dtype=np.float32).reshape(2, 4000) / 7.0)
subprocess.run([bench, "logmel", "--input", str(work / "signal.h5"), "--output", str(work / "logmel.h5"),
                "--sample-rate", "8000", "--n-fft", "256", "--hop", "64", "--n-mels", "32"], check=True)
with h5py.File(work / "logmel.h5", "r") as f:
    attrs = {key: f.attrs[key] for key in f.attrs}
    assert attrs["format_version"] == "1" and float(attrs["sample_rate"]) == 8000.0, attrs
    assert (int(attrs["n_fft"]), int(attrs["hop"]), int(attrs["n_mels"])) == (256, 64, 32), attrs
    assert attrs["mel_scale"] == "htk" and attrs["center"] == "false", attrs
    assert f["logmel"].shape[:2] == (2, 32), f["logmel"].shape
    print(f"logmel.h5: {f['logmel'].shape} with {attrs}")
