"""Helpers shared by the tests (pytest loads this file before them)."""
import pytest

import tessera


def run_and_resume(make, steps, path, description):
    """Builds a solver with make(), runs `steps` steps, saves a checkpoint at `path`, runs `steps`
    more; builds another with make(), loads the checkpoint into it and runs the same `steps`.
    Returns (the first solver, the resumed one, the checkpoint_info load_checkpoint returned)."""
    a = make()
    a.run_until(tessera.stop.after_steps(steps))
    tessera.io.save_checkpoint(a, path, description)
    saved_time = a.time()
    a.run_until(tessera.stop.after_steps(steps))
    b = make()
    info = tessera.io.load_checkpoint(b, path)
    assert b.step_count() == steps and b.time() == saved_time  # the clock is part of the state
    b.run_until(tessera.stop.after_steps(steps))
    return a, b, info


@pytest.fixture
def resumed():
    """run_and_resume, for a test to call."""
    return run_and_resume
