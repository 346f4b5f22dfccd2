# Generates the nanopb C sources from common/proto at build time (protoc + nanopb plugin).
find_program(PROTOC_EXECUTABLE protoc REQUIRED)
find_program(NANOPB_PLUGIN protoc-gen-nanopb REQUIRED)

function(digitizer_generate_proto out_sources out_dir)
  set(proto_dir ${CMAKE_SOURCE_DIR}/common/proto)
  set(gen_dir ${CMAKE_BINARY_DIR}/generated)
  file(MAKE_DIRECTORY ${gen_dir})
  # The working directory is the proto folder so the generator finds digitizer.options.
  add_custom_command(
    OUTPUT ${gen_dir}/digitizer.pb.c ${gen_dir}/digitizer.pb.h
    COMMAND ${PROTOC_EXECUTABLE} -I. --plugin=protoc-gen-nanopb=${NANOPB_PLUGIN}
            --nanopb_out=${gen_dir} digitizer.proto
    WORKING_DIRECTORY ${proto_dir}
    DEPENDS ${proto_dir}/digitizer.proto ${proto_dir}/digitizer.options
    COMMENT "nanopb: generating digitizer.pb.c/.h")
  set(${out_sources} ${gen_dir}/digitizer.pb.c PARENT_SCOPE)
  set(${out_dir} ${gen_dir} PARENT_SCOPE)
endfunction()
