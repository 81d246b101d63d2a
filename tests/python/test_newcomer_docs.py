"""What a newcomer reads before running anything says what the code does:
the friction help states the stability condition of the paper law
(a > f0 b, not a > b), the quickstart config says which reading of the
paper's "9 GPa" it uses, the README lists what cannot be posed, and
`analyze` and `plot` draw the same space-time field with one colour map.

The originals: docs/config.md called b only "state effect"; the quickstart
used mu = 9 GPa while every paper config uses E = 9 GPa, without a word; the
README had no "cannot (yet)" list; analyze's space-time figure used another
colour map than `slipstrip plot`.

Run: /usr/bin/python3 -m pytest tests/python/test_newcomer_docs.py
"""
import tomllib


def config_row(repo, section, key):
    """The row of `key` in the table of `[section]` of docs/config.md."""
    text = (repo / "docs/config.md").read_text()
    table = text[text.index(f"### [{section}]"):]
    return next(line for line in table.splitlines() if line.startswith(f"| `{key}` |"))


def test_friction_help_states_the_velocity_strengthening_condition(repo):
    a, b = config_row(repo, "friction", "a"), config_row(repo, "friction", "b")
    assert "a > f0 b" in a  # the paper law (Eq. S1) is velocity strengthening for a > f0 b
    assert "multiplies f0" in b and "f0 b" in b


def test_quickstart_states_its_material_reading(repo):
    text = (repo / "configs/quickstart.toml").read_text()
    config = tomllib.loads(text)
    assert config["material"]["shear_modulus"] == 9e9
    header = text[:text.index("[geometry]")] + text[text.index("[material]"):text.index("[material]") + 600]
    assert "PRINTED reading" in header and "mu = 9 GPa" in header and "E = 9 GPa" in header
    # ... which is not the paper configs' reading: theirs is E = 9 GPa.
    assert tomllib.loads((repo / "configs/reference.toml").read_text())["material"]["youngs_modulus"] == 9e9


def test_readme_lists_what_cannot_be_posed(repo):
    text = (repo / "README.md").read_text()
    section = text[text.index("## What it can pose, and what not (yet)"):]
    section = section[:section.index("\n## ", 1)]
    cannot = " ".join(row.split("|")[2] for row in section.splitlines() if row.startswith("| ")
                      and row.count("|") >= 3)
    for item in ("traction-free outer face", "adhesion or a cohesive strength", "finite faults",
                 "velocity steps", "time-varying loading"):
        assert item in cannot, item
    # Opening is modelled for in-plane pairs: the README says so on the "can" side.
    can = " ".join(row.split("|")[1] for row in section.splitlines() if row.startswith("| ")
                   and row.count("|") >= 3)
    assert "the faces open" in can
    # A 2D interface of identical or dissimilar bodies runs split over MPI processes.
    assert "identical or dissimilar bodies split over MPI processes with `mpirun -np P slipstrip-mpi run`" in can
    assert ("the same run file with its stations, restart points and `--resume` on any process count or by "
            "`slipstrip run`") in can


def test_analyze_and_plot_use_one_colour_map(slipstrip_module, repo, tmp_path, monkeypatch):
    from slipstrip import analysis, plots
    run = tmp_path / "tiny.h5"
    slipstrip_module.run(repo / "configs/quickstart.toml", run,
                         overrides={"geometry.nodes": 32, "time.duration_transits": 0.5,
                                    "output.snapshot_interval": 1e-5})
    drawn = []
    original = plots.spacetime_axes

    def spy(*args, **kwargs):
        mesh = original(*args, **kwargs)
        drawn.append(mesh.get_cmap().name)
        return mesh

    monkeypatch.setattr(plots, "spacetime_axes", spy)
    plots.spacetime(run, tmp_path / "plot.png")
    analysis.plot_space_time(run, analysis.read_run_info(run), tmp_path)
    assert drawn == [plots.SPACETIME_CMAP, plots.SPACETIME_CMAP]
