# cms_scratch_directory(<out> <prefix> <binary_dir>): a short path outside
# the build tree, unique to that build tree and the same at every configure
# (so that ccache and reruns find it): $TMPDIR (else /tmp)/<prefix>-<the
# first 10 hex digits of the MD5 of binary_dir>. Nothing is created. Used
# for the install test's prefix and the tests' Open MPI session directories
# (tests/CMakeLists.txt, examples/CMakeLists.txt).
function(cms_scratch_directory out prefix binary_dir)
  if(DEFINED ENV{TMPDIR} AND IS_DIRECTORY "$ENV{TMPDIR}")
    set(tmp "$ENV{TMPDIR}")
  else()
    set(tmp "/tmp")
  endif()
  string(MD5 id "${binary_dir}")
  string(SUBSTRING "${id}" 0 10 id)
  set(${out} "${tmp}/${prefix}-${id}" PARENT_SCOPE)
endfunction()
