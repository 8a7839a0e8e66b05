# Sourced by the scripts: Open MPI refuses to run as root unless told, and CI runs as root;
# --oversubscribe lets 2 ranks run on machines that report fewer slots.
if [ "$(id -u)" -eq 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
export OMPI_MCA_rmaps_base_oversubscribe=1
# Quiet Open MPI's warnings about missing high-speed fabrics in containers.
export OMPI_MCA_btl=self,vader OMPI_MCA_pml=ob1
