"""What every Python test shares: the cvc program, the shared data, a folder of this process's
own, and the default colon phantom made by `cvc phantom`. CTest sets PYTHONPATH=build/python,
CVC_BINARY (the cvc program), CVC_SHARED_DATA_DIR and CVC_TEST_TMP_DIR."""
import os
import subprocess

import pytest

CVC = os.environ["CVC_BINARY"]
SHARED = os.environ["CVC_SHARED_DATA_DIR"]
TMP = os.path.join(os.environ["CVC_TEST_TMP_DIR"], "python_%d" % os.getpid())
CT = os.path.join(SHARED, "ct", "ts_example_abdomen_3mm.nrrd")


def run_cvc(*arguments):
    return subprocess.run([CVC, *arguments], capture_output=True, text=True, stdin=subprocess.DEVNULL)


@pytest.fixture(scope="session")
def phantom():
    """The default colon phantom; its ground truth is beside it (colon.json)."""
    os.makedirs(TMP, exist_ok=True)
    volume = os.path.join(TMP, "colon.nrrd")
    made = run_cvc("phantom", "--force", "-o", volume)
    assert made.returncode == 0, made.stderr
    return volume
