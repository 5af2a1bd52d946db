"""Gauss-Legendre on a fixed grid: any reader gets the same state at the same time."""

import numpy as np
from analyzer_lab.lessons.analyzers.field.grid_flow import GridFlow


def rotation(ts):
    A = np.zeros((len(ts), 1, 2, 2))
    A[:, 0, 0, 1], A[:, 0, 1, 0] = np.cos(ts), -np.cos(ts)
    return A, np.zeros((len(ts), 1, 2))


def test_frames_and_samples_agree():
    r0 = np.array([[1.0, 0.0]])
    t = np.array([0.5, 1.0, 2.37, 3.0])
    whole = GridFlow(rotation, r0).at(t)
    live = GridFlow(rotation, r0)
    frames = [live.at(np.array([s]))[0] for s in t]
    assert np.array_equal(np.array(frames), whole)
    # x' = cos(t) y, y' = -cos(t) x: the angle is -sin(t)
    exact = np.stack([np.cos(np.sin(t)), -np.sin(np.sin(t))], axis=-1)
    assert np.max(np.abs(whole[:, 0] - exact)) < 1e-11
