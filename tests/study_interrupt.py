"""Shared by the study tests: start a study and interrupt it once a case
has finished."""
import glob
import os
import signal
import subprocess
import time


def interrupt_after_first_case(nct, study, out):
    """Run `nct study STUDY --out OUT`, send SIGINT once a case's
    summary.json exists, and check the study stopped with exit code 130
    and says how to resume. Returns its console text."""
    p = subprocess.Popen([nct, "study", study, "--out", out], stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    deadline = time.time() + 600
    while not glob.glob(os.path.join(out, "cases", "*", "summary.json")):
        assert p.poll() is None, "the study ended before it could be interrupted"
        assert time.time() < deadline, "no case finished in 600 s"
        time.sleep(0.2)
    p.send_signal(signal.SIGINT)
    text, _ = p.communicate(timeout=120)
    print(text)
    assert p.returncode == 130, f"interrupted: exit {p.returncode}, expected 130"
    assert "the same command resumes it" in text
    return text
