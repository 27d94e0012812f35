# ITK (Debian libinsighttoolkit5-dev) reads the volume files. Only load_volume_itk.cpp includes
# ITK headers; the rest of snert_core sees the ITK-free interface in load_volume.h.
find_package(ITK REQUIRED COMPONENTS ITKIONRRD ITKIONIFTI ITKIOMeta ITKIOVTK ITKIOGDCM)
# zlib: snert's own NIfTI sample reader and the size checks of compressed data.
find_package(ZLIB REQUIRED)

# ITK's imported targets carry no include directories. Give them to the one source that needs
# them, as system directories so ITK's own warnings stay out of our -Wall build. The IO
# factories are registered in code (RegisterOneFactory), so UseITK's generated registration
# header is not needed.
# /usr/include itself is left out: as -isystem it would break libstdc++'s #include_next.
set(_snert_itk_includes "")
foreach(_dir IN LISTS ITK_INCLUDE_DIRS)
    if(NOT _dir STREQUAL "/usr/include" AND NOT _dir IN_LIST _snert_itk_includes)
        list(APPEND _snert_itk_includes "-isystem" "${_dir}")
    endif()
endforeach()
set_source_files_properties(${CMAKE_CURRENT_SOURCE_DIR}/load_volume_itk.cpp PROPERTIES
    COMPILE_OPTIONS "${_snert_itk_includes}")
target_link_libraries(snert_core PRIVATE ${ITK_LIBRARIES} ZLIB::ZLIB)
