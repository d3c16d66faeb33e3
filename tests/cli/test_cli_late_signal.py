"""A signal once the outputs are committed does not turn a complete run into exit 130; before, it rolls back."""
import os
import signal
import sys

import pytest

import odnn_sep.io_utils as io_utils
import odnn_sep.signals.command as sim_command
from odnn_sep.cli import main


@pytest.fixture
def default_handlers():
    """Python's own SIGINT handler (KeyboardInterrupt) during the test, whatever the runner installed."""
    saved = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    for s, h in saved.items():
        signal.signal(s, h)


def test_sigint_after_commit_keeps_outputs_and_exits_0(tmp_path, monkeypatch, capsys, default_handlers):
    sent = []
    commit = io_utils._Transaction.commit

    def commit_then_interrupt(self):
        commit(self)
        sent.append(True)
        os.kill(os.getpid(), signal.SIGINT)   # Ctrl-C right after the outputs were committed

    monkeypatch.setattr(io_utils._Transaction, "commit", commit_then_interrupt)
    out = tmp_path / "fig2.csv"
    rc = main(["simulate", "figure2", "-o", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert sent == [True]
    assert rc == 0, err
    assert out.exists() and out.read_text().count("\n") > 10
    assert "Interrupted after the outputs were written; they are complete." in err
    assert "nothing of this run was kept" not in err
    assert [p.name for p in tmp_path.iterdir()] == ["fig2.csv"]   # no temporary folder left
    # an in-process call gets its handlers back
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_sigterm_after_commit_keeps_outputs_and_exits_0(tmp_path, monkeypatch, capsys, default_handlers):
    commit = io_utils._Transaction.commit

    def commit_then_terminate(self):
        commit(self)
        os.kill(os.getpid(), signal.SIGTERM)

    monkeypatch.setattr(io_utils._Transaction, "commit", commit_then_terminate)
    out = tmp_path / "fig2.csv"
    assert main(["simulate", "figure2", "-o", str(out), "--quiet"]) == 0
    assert out.exists()
    assert "Terminated after the outputs were written; they are complete." in capsys.readouterr().err


def test_sigint_before_commit_rolls_back_and_exits_130(tmp_path, monkeypatch, capsys, default_handlers):
    run = sim_command.run

    def run_then_interrupt(args):
        code = run(args)
        assert os.path.exists(args.output)    # written, not yet committed
        os.kill(os.getpid(), signal.SIGINT)
        return code

    monkeypatch.setattr(sim_command, "run", run_then_interrupt)
    out = tmp_path / "fig2.csv"
    assert main(["simulate", "figure2", "-o", str(out), "--quiet"]) == 130
    assert "Interrupted; nothing of this run was kept." in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_program_run_ignores_signals_through_shutdown(tmp_path, monkeypatch, default_handlers):
    out = tmp_path / "fig2.csv"
    monkeypatch.setattr(sys, "argv", ["odnn-sep", "simulate", "figure2", "-o", str(out), "--quiet"])
    assert main() == 0
    # the process only exits now: a late Ctrl-C must not end it with 130 and no message
    assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_IGN
