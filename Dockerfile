# rockbridge in a container: `docker build -t rockbridge .`, then for example
#   docker run --rm --user "$(id -u):$(id -g)" -v "$PWD:/work" rockbridge run configs/studies/paper-fig9.yaml
#
# Reproducible: every library (and the build backend) comes from requirements.lock, pinned and
# checked against its SHA-256 hashes. Ready at once: the numerical kernels are compiled at build
# time into NUMBA_CACHE_DIR, which stays set in the image, so a batch job's containers load them
# from there instead of each compiling them again (8–10 s). ROCKBRIDGE_PATHS lets a study's
# paths reach the bundled records from any working folder (a config's paths are otherwise
# confined to its own folder and the working folder: docs/studies.md, "Paths in configs").
FROM python:3.11-slim

ENV PYTHONDONTWRITEBYTECODE=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    MPLBACKEND=Agg \
    NUMBA_CACHE_DIR=/opt/rockbridge/numba-cache \
    ROCKBRIDGE_PATHS=/opt/rockbridge

RUN useradd --create-home --uid 1000 rockbridge
WORKDIR /opt/rockbridge

# The locked libraries first: this layer is rebuilt only when the lock changes.
COPY requirements.lock ./
RUN pip install --require-hashes -r requirements.lock

COPY pyproject.toml README.md .rockbridge ./
COPY rockbridge_cli ./rockbridge_cli
COPY configs ./configs
COPY records ./records
# The package itself (its dependencies are all in the lock), then every kernel compiled once.
# The cache is open to any user: `docker run --user` may give the container any uid.
RUN pip install --no-deps --no-build-isolation . \
    && python -m rockbridge_cli.warmup \
    && chmod -R a+rwX "$NUMBA_CACHE_DIR"

USER rockbridge
WORKDIR /work
ENTRYPOINT ["rockbridge"]
CMD ["--help"]
