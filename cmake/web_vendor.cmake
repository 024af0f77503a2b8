# The web review's pages take three.js from npm (ui/cli/web/vendor/package.json): its module,
# the glTF loader and the orbit controls, copied to OUT at build time with their bare imports
# ('three', '../utils/…') made relative, so a browser loads them from leafdig itself without an
# import map (which would be an inline script, forbidden by the pages' CSP).
#   cmake -DTHREE=…/node_modules/three -DOUT=dir -P web_vendor.cmake
file(MAKE_DIRECTORY "${OUT}")
function(vendor from to)
  file(READ "${THREE}/${from}" text)
  string(REPLACE "from 'three';" "from './three.module.min.js';" text "${text}")
  string(REPLACE "from '../utils/BufferGeometryUtils.js';" "from './BufferGeometryUtils.js';" text "${text}")
  file(WRITE "${OUT}/${to}.tmp" "${text}")
  file(COPY_FILE "${OUT}/${to}.tmp" "${OUT}/${to}" ONLY_IF_DIFFERENT)
  file(REMOVE "${OUT}/${to}.tmp")
endfunction()
file(COPY_FILE "${THREE}/build/three.module.min.js" "${OUT}/three.module.min.js" ONLY_IF_DIFFERENT)
file(COPY_FILE "${THREE}/LICENSE" "${OUT}/three.LICENSE.txt" ONLY_IF_DIFFERENT)
vendor(examples/jsm/loaders/GLTFLoader.js GLTFLoader.js)
vendor(examples/jsm/utils/BufferGeometryUtils.js BufferGeometryUtils.js)
vendor(examples/jsm/controls/OrbitControls.js OrbitControls.js)
