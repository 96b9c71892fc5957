# rockbridge in a container: `docker build -t rockbridge .`, then for example
#   docker run --rm -v "$PWD:/work" rockbridge run configs/studies/paper-fig9.yaml
FROM python:3.11-slim

ENV PYTHONDONTWRITEBYTECODE=1 \
    PIP_NO_CACHE_DIR=1 \
    MPLBACKEND=Agg \
    NUMBA_CACHE_DIR=/tmp/numba-cache

RUN useradd --create-home --uid 1000 rockbridge
WORKDIR /opt/rockbridge
COPY pyproject.toml README.md ./
COPY rockbridge_cli ./rockbridge_cli
COPY configs ./configs
COPY records ./records
# The same install command as README's first line.
RUN pip install .

USER rockbridge
WORKDIR /work
ENTRYPOINT ["rockbridge"]
CMD ["--help"]
