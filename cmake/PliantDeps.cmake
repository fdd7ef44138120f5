# Dependencies from Debian packages: libsuitesparse-dev (CHOLMOD), libmetis-dev,
# libxml2-dev, check, OpenMP (gcc's libgomp).  cmake/install-deps.sh installs them.
find_package(PkgConfig REQUIRED)
find_package(LibXml2 REQUIRED)
find_package(OpenMP REQUIRED COMPONENTS C)
find_package(ZLIB REQUIRED)

find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
find_library(CHOLMOD_LIBRARY cholmod REQUIRED)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig REQUIRED)
add_library(Pliant::cholmod INTERFACE IMPORTED)
target_include_directories(Pliant::cholmod INTERFACE ${CHOLMOD_INCLUDE_DIR})
target_link_libraries(Pliant::cholmod INTERFACE ${CHOLMOD_LIBRARY} ${SUITESPARSECONFIG_LIBRARY})

find_path(METIS_INCLUDE_DIR metis.h REQUIRED)
find_library(METIS_LIBRARY metis REQUIRED)
add_library(Pliant::metis INTERFACE IMPORTED)
target_include_directories(Pliant::metis INTERFACE ${METIS_INCLUDE_DIR})
target_link_libraries(Pliant::metis INTERFACE ${METIS_LIBRARY})

if(PLIANT_TESTS)
  pkg_check_modules(CHECK REQUIRED IMPORTED_TARGET check)
endif()
