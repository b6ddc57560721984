# FindHYPRE — hypre 2.26 (Debian 12 libhypre-dev) ships no CMake config.
# Provides the imported target HYPRE::HYPRE (BoomerAMG), which carries MPI (hypre's headers include
# mpi.h; Debian builds it against Open MPI). Link it PRIVATE: no polycut public header may include
# HYPRE.h or mpi.h.
find_path(HYPRE_INCLUDE_DIR HYPRE.h PATH_SUFFIXES hypre)
find_library(HYPRE_LIBRARY NAMES HYPRE)
find_package(MPI QUIET COMPONENTS C)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(HYPRE REQUIRED_VARS HYPRE_LIBRARY HYPRE_INCLUDE_DIR MPI_C_FOUND)
if(HYPRE_FOUND AND NOT TARGET HYPRE::HYPRE)
    add_library(HYPRE::HYPRE UNKNOWN IMPORTED)
    set_target_properties(HYPRE::HYPRE PROPERTIES
        IMPORTED_LOCATION "${HYPRE_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${HYPRE_INCLUDE_DIR}"
        INTERFACE_LINK_LIBRARIES MPI::MPI_C)
endif()
mark_as_advanced(HYPRE_INCLUDE_DIR HYPRE_LIBRARY)
