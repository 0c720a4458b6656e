# Everything `cmake --install` and `cpack -G DEB` put in place, in one file:
# the layer libraries with their public headers, the programs and their man
# pages, the device files, the exported CMake package ecatslave (targets
# ecatslave::<layer>, ecatslave::ecat-esigen, the function
# ecatslave_generate()) and the pkg-config file. Which headers are public:
# docs/api.md.
#
#   <prefix>/bin/ecat-{esigen,slave,master,conform}
#   <prefix>/<libdir>/libecatslave_<layer>.a (or .so.<version> with BUILD_SHARED_LIBS)
#   <prefix>/<libdir>/cmake/ecatslave/ecatslave{Config,ConfigVersion,Targets,Generate}.cmake
#   <prefix>/<libdir>/pkgconfig/ecatslave.pc
#   <prefix>/include/ecatslave/<layer>/*.hpp   (#include "coe/object_store.hpp")
#   <prefix>/share/ecatslave/{devices,profiles,schema}/
#   <prefix>/share/man/man1/ecat-*.1.gz
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(ECAT_INSTALL_INCLUDEDIR ${CMAKE_INSTALL_INCLUDEDIR}/ecatslave)
set(ECAT_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/ecatslave)
set(ECAT_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/ecatslave)

# SONAME: one number from project(VERSION). Before 1.0 every minor release
# may break the ABI, so 0.x libraries carry major.minor (libecatslave_esc.so.0.1);
# from 1.0 on, the major alone.
if(PROJECT_VERSION_MAJOR EQUAL 0)
  set(ECAT_SOVERSION ${PROJECT_VERSION_MAJOR}.${PROJECT_VERSION_MINOR})
else()
  set(ECAT_SOVERSION ${PROJECT_VERSION_MAJOR})
endif()

# With shared libraries, installed programs find them in ../lib and the
# libraries find each other in their own directory, so a staging prefix works
# without LD_LIBRARY_PATH (set per target below: the targets exist already).

# ecat_install_library(<target> <name> HEADERS <files...>)
# Installs layer <target> as libecatslave_<name> exported as ecatslave::<name>,
# and the listed headers (paths from the repository root) below include/ecatslave.
# The build tree gets the same ecatslave::<name> alias, so the examples can
# also be added with add_subdirectory().
function(ecat_install_library target name)
  cmake_parse_arguments(PARSE_ARGV 2 arg "" "" "HEADERS")
  get_target_property(type ${target} TYPE)
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  if(NOT type STREQUAL "INTERFACE_LIBRARY")
    set_target_properties(${target} PROPERTIES
      OUTPUT_NAME ecatslave_${name}
      VERSION ${PROJECT_VERSION}
      SOVERSION ${ECAT_SOVERSION}
      INSTALL_RPATH "$ORIGIN")
  endif()
  add_library(ecatslave::${name} ALIAS ${target})
  install(TARGETS ${target} EXPORT ecatslaveTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  foreach(header ${arg_HEADERS})
    get_filename_component(subdir ${header} DIRECTORY)
    install(FILES ${PROJECT_SOURCE_DIR}/${header} DESTINATION ${ECAT_INSTALL_INCLUDEDIR}/${subdir})
  endforeach()
endfunction()

# ecat_install_program(<target>): the program in bin/, exported as
# ecatslave::<target>, and its man page made by help2man from the program's own
# --help and --version (the CLI11 option definitions are the single source).
find_program(HELP2MAN_PROGRAM help2man)
function(ecat_install_program target description)
  add_executable(ecatslave::${target} ALIAS ${target})
  if(BUILD_SHARED_LIBS)
    set_target_properties(${target} PROPERTIES INSTALL_RPATH "$ORIGIN/../${CMAKE_INSTALL_LIBDIR}")
  endif()
  install(TARGETS ${target} EXPORT ecatslaveTargets RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  if(NOT HELP2MAN_PROGRAM)
    return()
  endif()
  set(page ${PROJECT_BINARY_DIR}/man/${target}.1)
  # gzip -9n as Debian policy §12.1 wants man pages (no name or time stamp
  # in the header, so the package is reproducible).
  add_custom_command(OUTPUT ${page}.gz
    COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/man
    COMMAND ${HELP2MAN_PROGRAM} --no-info --no-discard-stderr --section=1
            --name=${description} --output=${page} $<TARGET_FILE:${target}>
    COMMAND gzip -9nf ${page}
    DEPENDS ${target}
    COMMENT "Man page of ${target}"
    VERBATIM)
  add_custom_target(${target}_man ALL DEPENDS ${page}.gz)
  install(FILES ${page}.gz DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
endfunction()
if(NOT HELP2MAN_PROGRAM)
  message(STATUS "help2man not found: no man pages (scripts/install-deps installs it)")
endif()

# --- layers (docs/api.md: public API, and the internal headers they include) -------------
ecat_install_library(ecat_common common HEADERS
  common/cache_line.hpp common/clock.hpp common/command.hpp common/expected.hpp common/frame.hpp
  common/frame_builder.hpp common/frame_parser.hpp common/le.hpp common/source_pos.hpp)
ecat_install_library(od od HEADERS
  od/access.hpp od/axis_layout.hpp od/data_type.hpp od/device.hpp od/dictionary.hpp od/object.hpp
  od/modular_device.hpp)
ecat_install_library(esc esc HEADERS
  # public
  esc/esc.hpp esc/segment.hpp esc/pdi.hpp esc/esc_config.hpp esc/registers.hpp
  esc/al_status_code.hpp esc/esm.hpp esc/esm_config.hpp esc/esm_hooks.hpp
  esc/sii_interface.hpp esc/dc/vcd_trace.hpp esc/inner_delay_figures.hpp
  # internal, included by the public ones
  esc/access_side.hpp esc/esm_deferral.hpp esc/esm_transition.hpp esc/fmmu.hpp
  esc/register_bits.hpp esc/sync_manager.hpp esc/watchdog.hpp esc/dc/dc_unit.hpp
  esc/dc/latch_unit.hpp esc/dc/local_clock.hpp esc/dc/sync_unit.hpp esc/dc/time_loop.hpp
  esc/pass_hook.hpp esc/skip_index.hpp esc/eeprom_image.hpp)
ecat_install_library(coe coe HEADERS
  # public
  coe/coe_server.hpp coe/object_store.hpp coe/sdo_server.hpp coe/sdo_info.hpp
  coe/coe_protocol.hpp coe/mailbox_server.hpp coe/mailbox_service.hpp coe/emergency.hpp coe/error_field.hpp coe/diagnosis_history.hpp
  coe/foe_server.hpp coe/eoe_server.hpp coe/eoe_header.hpp coe/eoe_responder.hpp
  coe/process_data.hpp coe/pdo_config.hpp coe/parameter_store.hpp
  coe/sdo_abort.hpp coe/object_hooks.hpp coe/value.hpp coe/sync_controller.hpp
  coe/mailbox_header.hpp coe/storage_quota.hpp coe/module_ident_check.hpp
  # internal
  coe/mailbox_queue.hpp coe/pdo_mapping.hpp coe/recent_log.hpp coe/process_data_image.hpp coe/sm_bits.hpp
  coe/sync_checks.hpp coe/sync_mode.hpp)
ecat_install_library(ds402 ds402 HEADERS
  # public
  ds402/drive.hpp ds402/drive_overrides.hpp ds402/drive_config.hpp ds402/plant.hpp ds402/objects.hpp
  ds402/controlword.hpp ds402/statusword.hpp ds402/modes.hpp ds402/units.hpp
  ds402/svg_plot.hpp ds402/motion_trace.hpp ds402/od_binding.hpp
  # internal
  ds402/axis.hpp ds402/faults.hpp ds402/homing.hpp ds402/od_hooks.hpp ds402/option_codes.hpp
  ds402/profile.hpp ds402/profile_position.hpp ds402/state_machine.hpp ds402/touch_probe.hpp
  ds402/ip_buffer.hpp ds402/velocity_mode.hpp)
ecat_install_library(esi esi HEADERS
  # public
  esi/device_loader.hpp esi/esi_reader.hpp esi/esi_writer.hpp esi/sii_writer.hpp
  esi/sii_parser.hpp esi/sii_image.hpp esi/cpp_writer.hpp esi/device_error.hpp
  esi/xml_embedded.hpp esi/twin_import.hpp esi/esi_device_list.hpp esi/eni_reader.hpp esi/eni_devices.hpp
  # internal
  esi/sii_layout.hpp)
ecat_install_library(transport transport HEADERS
  transport/transport.hpp transport/in_memory_transport.hpp transport/pcap_file.hpp
  transport/raw_socket_transport.hpp transport/udp_transport.hpp transport/ip_allow_list.hpp
  # internal
  transport/unique_fd.hpp)
ecat_install_library(master master HEADERS
  master/master.hpp master/coe_client.hpp master/master_error.hpp master/sdo_abort.hpp
  master/sii.hpp master/slave_info.hpp master/mailbox.hpp master/datagram_link.hpp
  master/topology.hpp master/dc_delay.hpp master/redundant_transport.hpp master/dc_phase.hpp
  master/process_image_plan.hpp
  master/conformance/suite.hpp)
ecat_install_library(pdi_spi pdi_spi HEADERS
  # public
  pdi_spi/spi_bus.hpp pdi_spi/spi_pdi.hpp pdi_spi/lan9252_pdi.hpp pdi_spi/et1100_spi_pdi.hpp
  pdi_spi/spidev_bus.hpp pdi_spi/gpio_irq_line.hpp pdi_spi/pdi_spec.hpp
  pdi_spi/emulated_chip.hpp pdi_spi/emulated_lan9252.hpp pdi_spi/emulated_et1100_spi.hpp
  # internal
  pdi_spi/lan9252_registers.hpp pdi_spi/et1100_spi_registers.hpp)
ecat_install_library(slave slave HEADERS
  slave/application.hpp slave/chain.hpp slave/fault_catalogue.hpp slave/virtual_slave.hpp slave/slave_options.hpp
  slave/slave_stats.hpp slave/firmware.hpp slave/wake_times.hpp slave/spin_workers.hpp slave/frame_age.hpp
  slave/detached_pdi.hpp
  slave/eoe_init_check.hpp
  slave/cycle_timing.hpp)
ecat_install_library(control control HEADERS
  control/request_handler.hpp control/control_server.hpp control/event_queue.hpp control/event_watcher.hpp
  control/object_access.hpp control/network_view.hpp control/simulated_run.hpp control/control_error.hpp)
ecat_install_library(pdi_host pdi_host HEADERS
  pdi_host/pdi_host.hpp pdi_host/pdi_session.hpp pdi_host/pdi_chip.hpp pdi_client/ecat_pdi_protocol.h)

# --- firmware in the loop (docs/pdi-host.md): the C library a firmware links and the SOES HAL
#   <prefix>/<libdir>/libecat_pdi.a, <prefix>/include/ecatslave/ecat_pdi{,_protocol}.h,
#   <prefix>/share/ecatslave/soes-hal/esc_hw.{c,h}, <prefix>/<libdir>/ecatslave/libecat_{lan9252,spidev}_shim.so
set_target_properties(ecat_pdi PROPERTIES EXPORT_NAME ecat_pdi VERSION ${PROJECT_VERSION} SOVERSION ${ECAT_SOVERSION})
add_library(ecatslave::ecat_pdi ALIAS ecat_pdi)
install(TARGETS ecat_pdi EXPORT ecatslaveTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(FILES ${PROJECT_SOURCE_DIR}/pdi_client/ecat_pdi.h ${PROJECT_SOURCE_DIR}/pdi_client/ecat_pdi_protocol.h
        DESTINATION ${ECAT_INSTALL_INCLUDEDIR})
install(TARGETS ecat_lan9252_shim LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/ecatslave)
install(TARGETS ecat_spidev_shim LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/ecatslave)
install(FILES ${PROJECT_SOURCE_DIR}/pdi_client/soes-hal/esc_hw.c ${PROJECT_SOURCE_DIR}/pdi_client/soes-hal/esc_hw.h
        DESTINATION ${ECAT_INSTALL_DATADIR}/soes-hal)

# --- programs --------------------------------------------------------------------------
ecat_install_program(ecat-esigen "ESI, SII EEPROM image and C++ tables from an EtherCAT device description")
ecat_install_program(ecat-slave "virtual EtherCAT slave or chain of slaves on an interface, UDP or a pcap")
ecat_install_program(ecat-master "small EtherCAT master: scan, bring to Op, exchange process data")
ecat_install_program(ecat-conform "EtherCAT slave conformance tests")

# --- the Python package ecatslave (docs/control.md "Python") ----------------------------
# Pure Python, standard library only: where Debian's python3 finds it
# (/usr/lib/python3/dist-packages; not the multiarch libdir).
set(ECAT_INSTALL_PYTHONDIR lib/python3/dist-packages CACHE STRING "Where the ecatslave Python package is installed")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/python/ecatslave DESTINATION ${ECAT_INSTALL_PYTHONDIR}
        FILES_MATCHING PATTERN "*.py" PATTERN "__pycache__" EXCLUDE)

# --- device files, profiles, schema ---------------------------------------------------
install(DIRECTORY ${PROJECT_SOURCE_DIR}/xml/devices ${PROJECT_SOURCE_DIR}/xml/profiles
                  ${PROJECT_SOURCE_DIR}/xml/schema
        DESTINATION ${ECAT_INSTALL_DATADIR})
# The page of ecat-slave --http (docs/webview.md): found by the program as
# BINDIR/../share/ecatslave/www.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/web/www DESTINATION ${ECAT_INSTALL_DATADIR})
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/docs/api.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR})

# --- CMake package ----------------------------------------------------------------------
install(EXPORT ecatslaveTargets NAMESPACE ecatslave:: DESTINATION ${ECAT_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ecatslaveConfig.cmake.in
  ${PROJECT_BINARY_DIR}/ecatslaveConfig.cmake
  INSTALL_DESTINATION ${ECAT_INSTALL_CMAKEDIR}
  PATH_VARS ECAT_INSTALL_DATADIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/ecatslaveConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/ecatslaveConfig.cmake
              ${PROJECT_BINARY_DIR}/ecatslaveConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/ecatslaveGenerate.cmake
        DESTINATION ${ECAT_INSTALL_CMAKEDIR})
# In the build tree too: ecatslave_generate() for in-tree users.
include(${PROJECT_SOURCE_DIR}/cmake/ecatslaveGenerate.cmake)

# --- pkg-config --------------------------------------------------------------------------
# Relocatable: the prefix is found from the .pc file's own place (${pcfiledir}),
# so the same file serves a staging prefix and the Debian package's /usr.
file(RELATIVE_PATH ECAT_PC_TO_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" ECAT_PC_TO_PREFIX "${ECAT_PC_TO_PREFIX}")
# The headers need fmt; the libraries pugixml, libxml2 and libpcap, which a
# static archive passes on to every link and a shared library does not.
if(BUILD_SHARED_LIBS)
  set(ECAT_PC_REQUIRES "fmt nlohmann_json")
  set(ECAT_PC_REQUIRES_PRIVATE "pugixml libxml-2.0 libpcap")
else()
  set(ECAT_PC_REQUIRES "fmt nlohmann_json pugixml libxml-2.0 libpcap")
  set(ECAT_PC_REQUIRES_PRIVATE "")
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/ecatslave.pc.in ${PROJECT_BINARY_DIR}/ecatslave.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/ecatslave.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# --- Debian package (cpack -G DEB) ------------------------------------------------------
set(CPACK_PACKAGE_NAME ecatslave)
set(CPACK_PACKAGE_VENDOR "ecatslave")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "EtherCAT CoE slave stack, CiA402 drive and ESI/SII generator")
set(CPACK_PACKAGE_DESCRIPTION
  "A software EtherCAT Slave Controller, CANopen over EtherCAT, a CiA402 drive with a simulated motor, a small master and a generator of ESI files, SII images and C++ tables from one device description: the programs ecat-esigen, ecat-slave, ecat-master and ecat-conform, the C++20 libraries with their headers, CMake package and pkg-config file, and the device files.")
set(CPACK_PACKAGE_CONTACT "ecatslave maintainers <ecatslave@localhost>")
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION devel)
# Run-time libraries of the programs, found by dpkg-shlibdeps; the -dev
# packages are what find_package(ecatslave) and the headers need.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libfmt-dev, libpugixml-dev, libxml2-dev, libpcap-dev, libexpected-dev, nlohmann-json3-dev")
# The Python package ecatslave runs on python3; its pytest fixtures on python3-pytest.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "python3")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "cmake, pkg-config, libcli11-dev, python3-pytest")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
include(CPack)
