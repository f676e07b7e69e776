package lasonic.spy;

import java.awt.BasicStroke;
import java.awt.Graphics2D;
import java.awt.RenderingHints;
import java.awt.event.ActionEvent;
import java.awt.geom.AffineTransform;
import java.awt.geom.Rectangle2D;
import java.awt.image.BufferedImage;
import javax.swing.AbstractAction;
import javax.swing.Action;
import javax.swing.JDesktopPane;
import lasonic.grid_map_t;
import lcm.spy.ChannelData;
import lcm.spy.SpyPlugin;

/**
 * lcm-spy plugin for {@code lasonic.grid_map_t} (AGM_OPERATIONAL, AGM_TACTICAL): an Accumulative
 * Grid Map as an image in the odometry frame, centred on the robot. Cells with weight G &gt; 0
 * are light (more opaque for more weight), cells whose propagated weight Gp reaches the map's
 * threshold are dark; the dashed rectangle is the map's window, which follows the robot.
 */
public class GridMapPlugin implements SpyPlugin {
  @Override public boolean canHandle(long fingerprint) {
    return fingerprint == grid_map_t.LCM_FINGERPRINT;
  }

  @Override public Action getAction(final JDesktopPane desktop, final ChannelData cd) {
    return new AbstractAction("lasonic Accumulative Grid Map") {
      private static final long serialVersionUID = 1L;
      @Override public void actionPerformed(ActionEvent e) {
        if (desktop != null && cd != null) MapViewer.open(desktop, "AGM", cd, new Panel());
      }
    };
  }

  public static class Panel extends MapPanel {
    private static final long serialVersionUID = 1L;
    private grid_map_t m;
    private BufferedImage image;

    public Panel() {
      legend.add(new Object[] {Style.alpha(Style.AGM_WEIGHT, 160), "G > 0"});
      legend.add(new Object[] {Style.AGM_OCCUPIED, "Gp >= threshold (occupied)"});
      legend.add(new Object[] {Style.AGM_UNCHECKED, "occupied, only echoes the laser could not check (not remembered by the pilot)"});
    }

    /** Why the map cannot be drawn, or null. */
    static String problem(grid_map_t m) {
      if (m.width <= 0 || m.height <= 0) return "width/height must be > 0";
      if ((long) m.width * m.height != m.ncells) return "ncells " + m.ncells + " != width*height";
      if ((long) m.ncells > 16_000_000L) return "more than 16 million cells";
      if (m.g == null || m.gp == null || m.g.length < m.ncells || m.gp.length < m.ncells) return "arrays shorter than ncells";
      if (!finite(m.cell_size) || m.cell_size <= 0 || m.cell_size > 100) return "cell_size out of range";
      if (!finite(m.origin_x, m.origin_y)) return "origin not finite";
      return null;
    }

    @Override public void setMessage(Object msg) {
      m = null;
      image = null;
      if (!(msg instanceof grid_map_t)) {
        status = "not a grid_map_t: " + (msg == null ? "null" : msg.getClass().getName());
        return;
      }
      grid_map_t g = (grid_map_t) msg;
      String why = problem(g);
      if (why != null) {
        status = "invalid grid_map_t: " + why;
        return;
      }
      m = g;
      // One pixel per cell, image row 0 = the window's top row.
      image = new BufferedImage(m.width, m.height, BufferedImage.TYPE_INT_ARGB);
      int occupied = 0, weighted = 0, unchecked = 0;
      int weight = Style.AGM_WEIGHT.getRGB() & 0xffffff, occ = Style.AGM_OCCUPIED.getRGB(), unc = Style.AGM_UNCHECKED.getRGB();
      boolean heard = m.heard != null && m.heard.length >= m.ncells;
      for (int iy = 0; iy < m.height; iy++)
        for (int ix = 0; ix < m.width; ix++) {
          int i = iy * m.width + ix;
          int argb;
          if (m.gp[i] > 0 && m.gp[i] >= m.gp_threshold) {
            boolean only = heard && m.heard[i] == grid_map_t.HEARD_UNCHECKED;
            argb = only ? unc : occ;
            occupied++;
            if (only) unchecked++;
          } else if (m.g[i] > 0) {
            argb = ((int) (64 + 127 * Math.min(1.0, m.g[i] / 4.0)) << 24) | weight;
            weighted++;
          } else continue;
          image.setRGB(ix, m.height - 1 - iy, argb);
        }
      status = String.format("%dx%d cells of %.2f m: %d occupied (Gp >= %d), %d more with G > 0",
                             m.width, m.height, m.cell_size, occupied, m.gp_threshold, weighted);
      if (unchecked > 0) status += String.format("; %d of them only echoes the laser could not check made", unchecked);
    }

    @Override protected double[] centre() {
      if (m == null || m.robot_pose == null) return new double[] {0, 0};
      return new double[] {m.robot_pose.x, m.robot_pose.y};
    }

    @Override protected void paintWorld(Graphics2D g) {
      if (m == null) return;
      double cs = m.cell_size;
      AffineTransform at = new AffineTransform();
      at.translate(m.origin_x, m.origin_y + m.height * cs);
      at.scale(cs, -cs);
      g.setRenderingHint(RenderingHints.KEY_INTERPOLATION, RenderingHints.VALUE_INTERPOLATION_NEAREST_NEIGHBOR);
      g.drawImage(image, at, null);
      g.setColor(Style.NOTE);
      g.setStroke(new BasicStroke((float) (1 / scale), BasicStroke.CAP_BUTT, BasicStroke.JOIN_MITER, 10,
                                  new float[] {(float) (4 / scale), (float) (4 / scale)}, 0));
      g.draw(new Rectangle2D.Double(m.origin_x, m.origin_y, m.width * cs, m.height * cs));
      if (m.robot_pose != null) paintRobot(g, m.robot_pose.x, m.robot_pose.y, m.robot_pose.theta, Style.ROBOT_RADIUS);
    }
  }
}
