"""Work beyond one machine: ``--scheduler ADDRESS`` runs a regime map, a basin map or a design
study's charts on an existing dask.distributed cluster; the result must equal the local run. CI
runs it on a ``LocalCluster`` (the same code path as a remote cluster: a scheduler address)."""

import distributed  # in the test extra
import pytest

from slosh_bif.cli import main


@pytest.fixture(scope="module")
def scheduler():
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        yield cluster.scheduler_address


@pytest.mark.parametrize(
    "arguments, table",
    [
        (
            ["regimes", "--preset", "fig13", "--sigma-points", "3", "--abar-points", "3", "--tmax", "600"],
            "regimes.csv",
        ),
        (
            ["basins", "--preset", "fig10", "--set", "sigma=3", "--grid", "3", "3", "--tmax", "300"],
            "basins.csv",
        ),
        (
            ["study", "--preset", "fig10", "--set", "sigma=-1.2", "--vary", "beta=0:0.2:2", "--seeds", "0"]
            + ["--sigma-min", "-1.6", "--sigma-max", "-1.2", "--abar-min", "2.6", "--abar-max", "3.4"],
            "study.csv",
        ),
    ],
    ids=["regimes", "basins", "study"],
)
def test_a_sweep_on_a_dask_cluster_equals_the_local_one(tmp_path, scheduler, arguments, table):
    assert main([*arguments, "--scheduler", scheduler, "--out", str(tmp_path / "dask")]) == 0
    assert main([*arguments, "--workers", "2", "--out", str(tmp_path / "local")]) == 0
    assert (tmp_path / "dask" / table).read_text() == (tmp_path / "local" / table).read_text()


def test_a_scheduler_that_does_not_answer_is_a_one_line_error(tmp_path, capsys):
    code = main(
        [
            "regimes",
            "--preset",
            "fig13",
            "--sigma-points",
            "2",
            "--abar-points",
            "2",
            "--scheduler",
            "tcp://127.0.0.1:9",
            "--out",
            str(tmp_path),
        ]
    )
    err = capsys.readouterr().err
    assert code == 2 and "--scheduler tcp://127.0.0.1:9" in err and "Traceback" not in err


def test_a_service_that_is_not_a_scheduler_is_refused_in_seconds(tmp_path, capsys):
    """A server that greets with text (as an SSH or HTTP service may) is not read as a dask frame."""
    import socket
    import threading

    server = socket.create_server(("127.0.0.1", 0))
    port = server.getsockname()[1]

    def greet():
        for _ in range(2):
            try:
                conn, _ = server.accept()
            except OSError:  # the server closed once the command gave up
                return
            with conn:
                conn.sendall(b"HTTP/1.1 400 Bad Request\r\n\r\n")

    threading.Thread(target=greet, daemon=True).start()
    try:
        code = main(
            [
                "regimes",
                "--preset",
                "fig13",
                "--sigma-points",
                "2",
                "--abar-points",
                "2",
                "--scheduler",
                f"tcp://127.0.0.1:{port}",
                "--out",
                str(tmp_path),
            ]
        )
    finally:
        server.close()
    err = capsys.readouterr().err
    assert code == 2 and "is not a dask scheduler" in err and "Traceback" not in err


@pytest.mark.parametrize(
    "command", [["chart", "--preset", "fig10"], ["study", "--preset", "fig10", "--vary", "beta=0:0.2:2"]]
)
def test_a_chart_or_study_on_a_scheduler_that_does_not_answer_is_a_one_line_error(tmp_path, capsys, command):
    code = main([*command, "--scheduler", "tcp://127.0.0.1:9", "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2 and "--scheduler tcp://127.0.0.1:9" in err and "Traceback" not in err
    assert not any(tmp_path.iterdir())  # before any work
