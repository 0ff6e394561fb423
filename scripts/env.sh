# Sourced by the scripts: MPI as root, one BLAS thread per rank, /usr/bin
# first (the Debian python3 that has FEniCSx, not another one on PATH).
export PATH=/usr/bin:$PATH
export OPENBLAS_NUM_THREADS=1
if [ "$(id -u)" -eq 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
