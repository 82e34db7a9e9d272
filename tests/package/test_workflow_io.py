"""suspension_fabric.workflow_io.logged: the log of the thin Snakemake scripts."""

from __future__ import annotations

import sys

import pytest

from suspension_fabric.workflow_io import logged


def failing_step():
    raise ValueError("bad input table")


@pytest.mark.parametrize("error", [ValueError, SystemExit, KeyboardInterrupt])
def test_error_in_block_is_logged_with_traceback_and_reraised(tmp_path, capfd, error):
    """An exception in the block (any BaseException: also sys.exit and Ctrl-C) is written to the
    log with its traceback (the raising function and the message), after the block's stdout and
    stderr; it propagates unchanged; 'error: see <log>' goes to the real stderr (fd 2); and
    sys.stdout / sys.stderr are the original objects again afterwards. The log's missing
    parent folder is created."""
    log_path = tmp_path / "logs" / "rule" / "job.log"
    stdout, stderr = sys.stdout, sys.stderr

    def step():
        if error is ValueError:
            failing_step()
        raise error("bad input table")

    with pytest.raises(error) as raised:
        with logged(log_path):
            print("reading the tables")
            print("a warning", file=sys.stderr)
            step()
    assert raised.type is error and "bad input table" in str(raised.value)
    assert sys.stdout is stdout and sys.stderr is stderr

    text = log_path.read_text()
    assert text.index("reading the tables") < text.index("a warning") < text.index("Traceback")
    assert f"{error.__name__}: bad input table" in text
    if error is ValueError:
        assert "in failing_step" in text and 'raise ValueError("bad input table")' in text
    captured = capfd.readouterr()
    assert f"error: see {log_path}" in captured.err
    assert "reading the tables" not in captured.out + captured.err


def test_successful_block_logs_output_and_no_error(tmp_path, capfd):
    """Without an error the log holds the block's output only (a previous log is replaced),
    nothing is reported on stderr and the streams are restored."""
    log_path = tmp_path / "job.log"
    log_path.write_text("old run\n")
    stdout, stderr = sys.stdout, sys.stderr
    with logged(log_path):
        print("done", 42)
    assert sys.stdout is stdout and sys.stderr is stderr
    assert log_path.read_text() == "done 42\n"
    captured = capfd.readouterr()
    assert captured.out == "" and "error" not in captured.err
    print("after the block")
    assert capfd.readouterr().out == "after the block\n"
