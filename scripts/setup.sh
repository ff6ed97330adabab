# Set-up shared by the make targets (sourced: `source scripts/setup.sh`): each target installs
# what it needs itself, so that `make fmu` or `make lammps-plugin` works on a fresh machine
# as `make test` does (before, only scripts/test.sh installed libclang-dev, and `make fmu`
# panicked inside bindgen).

# Installs the Debian packages among "$@" that are missing (apt-get; through sudo unless root).
need_debian_packages() {
    local missing=() pkg sudo=""
    for pkg in "$@"; do
        dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    if ! command -v apt-get >/dev/null; then
        echo "needs the Debian packages ${missing[*]} (or their equivalents); apt-get is not here to install them" >&2
        return 1
    fi
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    echo "installing ${missing[*]} (apt-get)" >&2
    $sudo apt-get update -qq
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}"
}

# Makes .venv (python3 -m venv) and installs the PyPI packages among "$@" it lacks, each given
# as pip takes it (name or name==version); `import` names are not checked, pip is asked.
need_python_packages() {
    if [ ! -x .venv/bin/python ]; then
        need_debian_packages python3-venv
        python3 -m venv .venv
    fi
    local missing=() spec name
    for spec in "$@"; do
        name=${spec%%==*}
        .venv/bin/python -m pip show --quiet "$name" >/dev/null 2>&1 || missing+=("$spec")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    echo "installing ${missing[*]} into .venv (pip)" >&2
    .venv/bin/python -m pip install --quiet --disable-pip-version-check "${missing[@]}"
}
