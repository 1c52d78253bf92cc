# One image for the four programs: master, vehicle_node, track_node, soil_node.
FROM debian:bookworm-slim
WORKDIR /src
COPY . .
RUN scripts/install-deps.sh \
 && cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DRAILCOSIM_BUILD_TESTS=OFF -DRAILCOSIM_BUILD_BENCH=OFF \
 && cmake --build build -j "$(nproc)" \
 && install -m 755 build/bin/master build/bin/vehicle_node build/bin/track_node build/bin/soil_node \
      /usr/local/bin/
ENV PATH=/usr/local/bin:$PATH
